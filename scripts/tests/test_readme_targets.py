#!/usr/bin/python3
"""scripts/readme_targets.py's realistic-set rows on small CSVs written here: the 95 % row carries the
payload readers' ceiling from realistic_ceiling_summary.csv when the run had --ceiling, and nothing
when it did not, and the thorough profile's rate beside the default's when it ran; update_readme.py's table of the held-out seed (results/realistic_seed2/) carries the
ceiling as a share of each bin's tags, and its tables of other families give no rate for a bin of false
detections only; the corner table compares two detectors on the tags both found right.
Usage: test_readme_targets.py SOURCE_DIR (run by ctest)."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(sys.argv[1], "scripts"))
import readme_targets  # noqa: E402
import update_readme  # noqa: E402

SUMMARY = ("set,seed,family,frames,size_bin,bin_lo_px,bin_hi_px,detector,tags,detected,detection_rate,wrong_id_tags\n"
           "realistic,1,36h11,2,20-24,20,24,tagbench,10,8,0.8,0\n"
           "realistic,1,36h11,2,20-24,20,24,libapriltag-d1,10,5,0.5,\n"
           "realistic,1,36h11,2,all,,,tagbench,10,8,0.8,0\n"
           "realistic,1,36h11,2,all,,,libapriltag-d1,10,5,0.5,\n")
CEILING = ("set,seed,family,frames,size_bin,contrast_band,tags,ceiling_area,ceiling_point,ceiling_either\n"
           "realistic,1,36h11,2,20-24,<10,3,1,2,2\n"
           "realistic,1,36h11,2,20-24,all,10,8,7,9\n")
SUMMARY2 = ("set,seed,family,frames,size_bin,detector,tags,detection_rate,rate_lo95,rate_hi95,wrong_id_tags,"
            "false_detections\n"
            "realistic,2,36h11,2,20-24,tagbench,10,0.8,0.6,0.9,0,0\n"
            "realistic,2,36h11,2,20-24,libapriltag-d1,10,0.5,0.3,0.7,1,2\n"
            "realistic,2,36h11,2,all,tagbench,10,0.8,0.6,0.9,0,0\n"
            "realistic,2,36h11,2,all,libapriltag-d1,10,0.5,0.3,0.7,1,2\n")


def write(d, name, text):
    with open(os.path.join(d, name), "w") as f:
        f.write(text)


class RealisticRows(unittest.TestCase):
    def test_the_95_row_names_the_ceiling_of_its_bin(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "realistic_summary.csv", SUMMARY)
            write(d, "realistic_ceiling_summary.csv", CEILING)
            rows = readme_targets._realistic(d)
            self.assertEqual(len(rows), 2)
            self.assertIn("80 % (libapriltag d1 50 %)", rows[1][1])
            self.assertIn("at most 9/10 = 90.0 %", rows[1][1])
            self.assertEqual(rows[1][2], "not met")
            self.assertEqual(rows[0][2], "**met**")

    def test_without_a_ceiling_run_the_row_says_only_the_rates(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "realistic_summary.csv", SUMMARY)
            rows = readme_targets._realistic(d)
            self.assertEqual(rows[1][1], "80 % (libapriltag d1 50 %)")


    def test_the_thorough_profiles_rate_stands_beside_and_does_not_decide(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "realistic_summary.csv", SUMMARY + "realistic,1,36h11,2,20-24,20,24,tagbench-thorough,10,10,1.0,0\n")
            rows = readme_targets._realistic(d)
            self.assertEqual(rows[1][1], "80 % (libapriltag d1 50 %; thorough profile 10 of 10, 100.0 %)")
            self.assertEqual(rows[1][2], "not met")  # the target is the default profile's

    def test_the_thorough_profiles_rate_is_not_rounded_up_to_the_target(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "realistic_summary.csv",
                  SUMMARY + "realistic,1,36h11,2,20-24,20,24,tagbench-thorough,188,178,0.946809,0\n")
            rows = readme_targets._realistic(d)
            self.assertIn("thorough profile 178 of 188, 94.7 %", rows[1][1])
            self.assertEqual(rows[1][2], "not met")  # the target is the default profile's


class HeldOutTable(unittest.TestCase):
    def test_the_seed2_table_has_the_ceiling_column_and_each_detectors_rate(self):
        with tempfile.TemporaryDirectory() as d:
            os.mkdir(os.path.join(d, "realistic_seed2"))
            write(d, "realistic_seed2/realistic_summary.csv", SUMMARY2)
            write(d, "realistic_seed2/realistic_ceiling_summary.csv", CEILING)
            lines = update_readme.realistic_seed2_table(d).splitlines()
            self.assertIn("Readable from the true corners, %", lines[0])
            self.assertEqual(len(lines), 4)  # header, rule, 20-24 px, all
            self.assertTrue(lines[2].startswith("| 20-24 px | 10 | 90 | 80 [60-90] | 50 [30-70], 1 wrong id, 2 false |"), lines[2])
            self.assertIn("| all | 10 | - |", lines[3])  # no ceiling row for "all" in this CSV


class FamilyTables(unittest.TestCase):
    def test_a_bin_of_false_detections_only_has_no_rate(self):
        with tempfile.TemporaryDirectory() as d:
            os.mkdir(os.path.join(d, "realistic_16h5"))
            write(d, "realistic_16h5/realistic_summary.csv",
                  SUMMARY2.replace("36h11", "16h5") + "realistic,1,16h5,2,<12,tagbench,0,,,,,3\n")
            lines = update_readme.realistic_family_table(d, "16h5").splitlines()
            self.assertNotIn("Readable", lines[0])  # no ceiling column
            self.assertTrue(lines[2].startswith("| 20-24 px | 10 | 80 [60-90] | 50 [30-70], 1 wrong id, 2 false |"),
                            lines[2])
            self.assertEqual(lines[4], "| <12 px | 0 | -, 3 false | - |")  # no libapriltag row there: "-"


class CornerTable(unittest.TestCase):
    def test_each_pair_is_compared_on_the_tags_both_found_with_the_right_id(self):
        head = "frame,tag,detector,detected,wrong_id,corner_rms_px\n"
        # Tag (0,0): both found; (0,1): ours only; (0,2): the peer's is a wrong id; (1,0): both found.
        csv = head + ("0,0,tagbench,1,0,0.1\n0,0,libapriltag-d1,1,0,0.3\n"
                      "0,1,tagbench,1,0,5.0\n0,1,libapriltag-d1,0,0,\n"
                      "0,2,tagbench,1,0,7.0\n0,2,libapriltag-d1,1,1,0.2\n"
                      "1,0,tagbench,1,0,0.2\n1,0,libapriltag-d1,1,0,0.5\n")
        with tempfile.TemporaryDirectory() as d:
            write(d, "realistic.csv", csv)
            for sub in ("realistic_seed2", "realistic_16h5", "realistic_25h9", "realistic_linear"):
                os.mkdir(os.path.join(d, sub))
                write(d, sub + "/realistic.csv", head)
            lines = update_readme.realistic_corners(d).splitlines()
            self.assertEqual(len(lines), 7)  # header, rule, five sets
            self.assertTrue(lines[2].startswith("| 36h11, seed 1 | 2: 0.150 / 0.200 vs 0.400 / 0.500 | - | - |"), lines[2])
            self.assertEqual(lines[3], "| 36h11, seed 2 | - | - | - |")


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

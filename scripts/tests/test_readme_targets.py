#!/usr/bin/python3
"""scripts/readme_targets.py's realistic-set rows on small CSVs written here: the 95 % row carries the
payload readers' ceiling from realistic_ceiling_summary.csv when the run had --ceiling, and nothing
when it did not.
Usage: test_readme_targets.py SOURCE_DIR (run by ctest)."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(sys.argv[1], "scripts"))
import readme_targets  # noqa: E402

SUMMARY = ("set,seed,family,frames,size_bin,bin_lo_px,bin_hi_px,detector,tags,detected,detection_rate,wrong_id_tags\n"
           "realistic,1,36h11,2,20-24,20,24,tagbench,10,8,0.8,0\n"
           "realistic,1,36h11,2,20-24,20,24,libapriltag-d1,10,5,0.5,\n"
           "realistic,1,36h11,2,all,,,tagbench,10,8,0.8,0\n"
           "realistic,1,36h11,2,all,,,libapriltag-d1,10,5,0.5,\n")
CEILING = ("set,seed,family,frames,size_bin,contrast_band,tags,ceiling_area,ceiling_point,ceiling_either\n"
           "realistic,1,36h11,2,20-24,<10,3,1,2,2\n"
           "realistic,1,36h11,2,20-24,all,10,8,7,9\n")


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


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

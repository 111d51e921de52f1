#!/usr/bin/python3
"""scripts/loss_breakdown.py on small summary CSVs written here (a sweep's and the realistic set's):
the missed count per stage per step and detector, the detectors side by side in the order given,
detectors that cannot explain left out, and one-line refusals.
Usage: test_loss_breakdown.py SOURCE_DIR (run by ctest)."""
import os
import subprocess
import sys
import tempfile
import unittest

SRC = sys.argv[1]
SCRIPT = os.path.join(SRC, "scripts", "loss_breakdown.py")
STAGES = ["no_cluster", "no_segment", "no_quad", "quad_rejected", "misread", "wrong_id", "duplicate", "below_margin",
          "withdrawn"]
LOST = ",".join("lost_" + s for s in STAGES)
SWEEP = (f"experiment,condition,step,step_unit,detector,frames,detected,ms_median,{LOST}\n"
         "distance,none,10,m,tagbench-full,4,4,1.0,0,0,0,0,0,0,0,0,0\n"
         "distance,none,10,m,aruco,4,3,1.0,,,,,,,,,\n"
         "distance,none,10,m,tagbench-half,4,2,1.0,0,1,0,0,1,0,0,0,0\n"
         "distance,none,30,m,tagbench-full,4,1,1.0,1,2,0,0,0,0,0,0,0\n"
         "distance,none,30,m,tagbench-half,4,0,1.0,4,0,0,0,0,0,0,0,0\n")
REALISTIC = (f"set,seed,family,frames,size_bin,bin_lo_px,bin_hi_px,detector,tags,detected,{LOST}\n"
             "realistic,5,36h11,2,12-16,12,16,tagbench-full,5,2,0,3,0,0,0,0,0,0,0\n"
             "realistic,5,36h11,2,all,,,tagbench-full,9,6,0,3,0,0,0,0,0,0,0\n")


def run(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True)


class LossBreakdown(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="test_loss_breakdown.")
        cls.sweep = os.path.join(cls.tmp, "fig10_distance_summary.csv")
        cls.realistic = os.path.join(cls.tmp, "realistic_summary.csv")
        with open(cls.sweep, "w") as f:
            f.write(SWEEP)
        with open(cls.realistic, "w") as f:
            f.write(REALISTIC)

    def test_csv_per_step_and_detector_without_the_detectors_that_cannot_say(self):
        r = run(self.sweep)
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertEqual(lines[0], f"step,step_unit,detector,frames,detected,missed,{LOST},source")
        self.assertEqual(len(lines), 5)
        self.assertNotIn("aruco", r.stdout)
        self.assertEqual(lines[2], "10,m,tagbench-half,4,2,2,0,1,0,0,1,0,0,0,0,fig10_distance_summary.csv")

    def test_two_profiles_side_by_side_in_markdown(self):
        r = run(self.sweep, "--detectors", "tagbench-half,tagbench-full", "--format", "markdown")
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertEqual(lines[0], "| step (m) | detector | frames | detected | no_cluster | no_segment | misread |")
        self.assertEqual([l.split(" | ")[1] for l in lines[2:]],
                         ["tagbench-half", "tagbench-full", "tagbench-half", "tagbench-full"])
        self.assertEqual(lines[4], "| 30 | tagbench-half | 4 | 0 | 4 | 0 | 0 |")

    def test_realistic_bins_and_out_file(self):
        out = os.path.join(self.tmp, "b.csv")
        r = run(self.realistic, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, "")
        with open(out) as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[1], "12-16,black_square_px,tagbench-full,5,2,3,0,3,0,0,0,0,0,0,0,realistic_summary.csv")

    def test_refusals_are_one_line(self):
        old = os.path.join(self.tmp, "old.csv")
        with open(old, "w") as f:
            f.write("experiment,condition,step,step_unit,detector,frames,detected\ndistance,none,2,m,aruco,1,1\n")
        for args, why in [([old], "no lost_* columns"), ([self.sweep, "--detectors", "nope"], "no detector 'nope'"),
                          ([os.path.join(self.tmp, "missing.csv")], "missing.csv")]:
            r = run(*args)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn(why, r.stderr)
            self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
            self.assertEqual(r.stdout, "")


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

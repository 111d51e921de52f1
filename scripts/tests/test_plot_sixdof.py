#!/usr/bin/python3
"""scripts/plot_sixdof.py on a small 6-DoF sweep (tagbench raytrace sixdof, 12 frames, two detectors):
it draws the grid (four outcomes by six pose variables) with one legend entry per detector and names
its inputs in the sidecar; a folder without a sixdof summary, or with another sweep's, is refused with
one line and no figure. Usage: test_plot_sixdof.py TAGBENCH_BIN SOURCE_DIR (run by ctest)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

BIN, SRC = sys.argv[1], sys.argv[2]
PY = "/usr/bin/python3"
PLOT = os.path.join(SRC, "scripts", "plot_sixdof.py")


class PlotSixdof(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="test_plot_sixdof.")
        cls.sweep = os.path.join(cls.tmp, "sweep")
        subprocess.run([BIN, "raytrace", "sixdof", "--frames", "12", "--detectors", "tagbench-paper,aruco",
                        "--processes", "1", "--cache", os.path.join(cls.tmp, "cache"), "--out", cls.sweep],
                       check=True, capture_output=True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_draws_the_grid_with_one_entry_per_detector(self):
        r = subprocess.run([PY, PLOT, self.sweep], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        png = os.path.join(self.sweep, "sixdof.png")
        self.assertTrue(os.path.getsize(png) > 10000)
        with open(os.path.join(self.sweep, "sixdof_plot.json")) as f:
            doc = json.load(f)
        self.assertEqual(doc["rows"], ["detection_rate", "corner_rms_px", "orientation_error_deg", "distance_error_m"])
        self.assertEqual(doc["columns"], ["distance_m", "phi_deg", "tilt_axis_deg", "roll_deg", "image_x", "image_y"])
        self.assertEqual(doc["legend"], ["ours (paper profile), full resolution", "OpenCV 4.6 aruco (APRILTAG refine)"])
        self.assertEqual([n for n in os.listdir(self.sweep) if ".tmp" in n], [])

    def test_a_folder_without_a_sixdof_summary_is_refused(self):
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty, exist_ok=True)
        r = subprocess.run([PY, PLOT, empty], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("sixdof_summary.csv", r.stderr)
        self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(empty, "sixdof.png")))
        other = os.path.join(self.tmp, "other")
        os.makedirs(other, exist_ok=True)
        with open(os.path.join(other, "sixdof_summary.csv"), "w") as f:
            f.write("experiment,condition,step\nangle,none,0\n")
        shutil.copy(os.path.join(self.sweep, "sixdof.json"), other)
        r = subprocess.run([PY, PLOT, other], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("has no sixdof rows", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(other, "sixdof.png")))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

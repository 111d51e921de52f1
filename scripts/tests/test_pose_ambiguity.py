#!/usr/bin/python3
"""scripts/pose_ambiguity.py on a tiny dataset and detection file written here: a detection whose pose
is the wrong solution of the planar ambiguity and whose alternative is right is counted as fixable, a
right pose is not counted, the CSV has a row per detected frame, and bad inputs get one-line refusals.
Usage: test_pose_ambiguity.py SOURCE_DIR (run by ctest)."""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(sys.argv[1], "scripts", "pose_ambiguity.py")
I = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def rot_x(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


CORNERS = [[10, 10], [30, 10], [30, 30], [10, 30]]


def frame(name, phi):
    return {"file": name, "id": 7, "corners": CORNERS, "R": I, "black_square_px": 20,
            "view": {"phi_deg": phi, "distance_m": 3}, "camera_effects": {"noise_sigma": 1, "defocus_sigma_px": 0.5}}


def detection(R, alt_R):
    return {"id": 7, "corners": CORNERS, "decision_margin": 50,
            "pose": {"R": R, "reprojection_rms_px": 0.1},
            "pose_alternative": {"R": alt_R, "reprojection_rms_px": 0.2}}


def run(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True)


class PoseAmbiguity(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = self.dir.name
        with open(os.path.join(d, "truth.json"), "w") as f:
            json.dump({"frames": [frame("a.png", 5), frame("b.png", 25), frame("c.png", 45)]}, f)
        with open(os.path.join(d, "det.json"), "w") as f:
            json.dump({"images": [{"input": "/x/a.png", "detections": [detection(rot_x(30), I)]},
                                  {"input": "/x/b.png", "detections": [detection(rot_x(1), rot_x(40))]},
                                  {"input": "/x/c.png", "detections": []}]}, f)

    def tearDown(self):
        self.dir.cleanup()

    def test_a_wrong_pick_with_a_right_alternative_is_fixable(self):
        d = self.dir.name
        out = os.path.join(d, "rows.csv")
        p = run(d, os.path.join(d, "det.json"), "--csv", out)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("detected 2;", p.stdout)
        self.assertIn("> 10 deg: 1", p.stdout)
        self.assertIn("within 5 deg: 1 (100 %)", p.stdout)
        self.assertIn("whose alternative is > 10 deg off: 1", p.stdout)  # frame b's alternative is 40 deg off
        with open(out) as fh:
            rows = list(csv.DictReader(fh))
        self.assertEqual([r["file"] for r in rows], ["a.png", "b.png"])
        self.assertAlmostEqual(float(rows[0]["err_deg"]), 30, places=6)
        self.assertAlmostEqual(float(rows[0]["alt_err_deg"]), 0, places=6)

    def test_bad_inputs_get_one_line(self):
        d = self.dir.name
        missing = run(os.path.join(d, "nowhere"), os.path.join(d, "det.json"))
        self.assertNotEqual(missing.returncode, 0)
        self.assertEqual(len(missing.stderr.strip().splitlines()), 1)
        self.assertIn("truth.json", missing.stderr)
        with open(os.path.join(d, "bad.json"), "w") as f:
            f.write("{not json")
        bad = run(d, os.path.join(d, "bad.json"))
        self.assertNotEqual(bad.returncode, 0)
        self.assertEqual(len(bad.stderr.strip().splitlines()), 1)
        self.assertIn("bad.json: not JSON", bad.stderr)
        with open(os.path.join(d, "other.json"), "w") as f:
            json.dump({"something": []}, f)
        other = run(d, os.path.join(d, "other.json"))
        self.assertIn('other.json: no "images" list', other.stderr)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

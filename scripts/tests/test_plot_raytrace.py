#!/usr/bin/python3
"""scripts/plot_raytrace.py on a small ray-traced sweep (tagbench raytrace distance, 2 trials at 2 and
25 m): with the runs made outside the build it draws their curves, copies their CSVs into
RESULTS/external/ and names them in the sidecar; without them it draws our detectors only; with only
results/external/ (a clone without ../shared) it plots from there; a broken external CSV is refused.
Usage: test_plot_raytrace.py TAGBENCH_BIN SOURCE_DIR (run by ctest)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

BIN, SRC = sys.argv[1], sys.argv[2]
PY = "/usr/bin/python3"
PLOT = os.path.join(SRC, "scripts", "plot_raytrace.py")
# The committed copies: the test needs no ../shared beside the clone.
EXTERNAL = os.path.join(SRC, "results", "external")
FILES = ["artoolkitplus_fig10_distance.csv", "java_apriltag1_fig10_distance.csv"]
OURS = ["ours (paper profile), full resolution", "OpenCV 4.6 aruco (APRILTAG refine)"]


class PlotRaytrace(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="test_plot_raytrace.")
        cls.sweep = os.path.join(cls.tmp, "sweep")
        subprocess.run([BIN, "raytrace", "distance", "--trials", "2", "--distances", "2,25", "--detectors",
                        "tagbench-paper,aruco", "--processes", "1", "--cache", os.path.join(cls.tmp, "cache"),
                        "--out", cls.sweep], check=True, capture_output=True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def results_copy(self, name):
        d = os.path.join(self.tmp, name)
        shutil.copytree(self.sweep, d)
        return d

    def plot(self, results, *extra):
        return subprocess.run([PY, PLOT, results, *extra, "distance"], capture_output=True, text=True)

    def sidecar(self, results):
        with open(os.path.join(results, "fig10_distance_plot.json")) as f:
            return json.load(f)

    def test_with_external_runs_draws_them_and_copies_them(self):
        src = os.path.join(self.tmp, "shared_external")
        os.makedirs(src, exist_ok=True)
        for name in FILES:
            shutil.copy(os.path.join(EXTERNAL, name), src)
        results = self.results_copy("with")
        r = self.plot(results, "--external", src)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(results, "fig10_distance.png")) > 0)
        doc = self.sidecar(results)
        self.assertEqual(doc["legend"][:2], OURS)
        self.assertIn("Java AprilTag 1 (paper's code, defaults; run outside the build)", doc["legend"])
        art = [x for x in doc["legend"] if x.startswith("ARToolKitPlus") and x.endswith("run outside the build)")]
        self.assertEqual(len(art), 2, doc["legend"])
        self.assertEqual(sorted(u["file"] for u in doc["external_runs"]), sorted("external/" + n for n in FILES))
        for u in doc["external_runs"]:
            self.assertTrue(u["read_from"].endswith(os.path.join("shared_external", os.path.basename(u["file"]))))
            self.assertFalse(u["same_frames_as_this_sweep"])  # 2 trials, 2 steps: not make bench's frames
        for name in FILES:
            with open(os.path.join(src, name), "rb") as a, open(os.path.join(results, "external", name), "rb") as b:
                self.assertEqual(a.read(), b.read())

    def test_without_external_runs_draws_as_before(self):
        results = self.results_copy("without")
        r = self.plot(results, "--external", os.path.join(self.tmp, "no_such_folder"))
        self.assertEqual(r.returncode, 0, r.stderr)
        doc = self.sidecar(results)
        self.assertEqual(doc["legend"], OURS)
        self.assertEqual(doc["external_runs"], [])
        self.assertFalse(os.path.exists(os.path.join(results, "external")))

    def test_a_clone_without_shared_plots_from_results_external(self):
        results = self.results_copy("clone")
        os.makedirs(os.path.join(results, "external"))
        shutil.copy(os.path.join(EXTERNAL, FILES[1]), os.path.join(results, "external"))
        r = self.plot(results, "--external", os.path.join(self.tmp, "no_such_folder"))
        self.assertEqual(r.returncode, 0, r.stderr)
        doc = self.sidecar(results)
        self.assertEqual(doc["legend"], OURS + ["Java AprilTag 1 (paper's code, defaults; run outside the build)"])
        self.assertEqual([u["read_from"] for u in doc["external_runs"]], ["clone/external/" + FILES[1]])

    def test_another_familys_distance_sweep_adds_the_families_figure(self):
        results = self.results_copy("families")
        r = self.plot(results, "--external", os.path.join(self.tmp, "no_such_folder"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(results, "fig10_distance_families.png")))  # 36h11 alone
        subprocess.run([BIN, "raytrace", "distance", "--family", "16h5", "--trials", "1", "--distances", "4,25",
                        "--detectors", "tagbench", "--processes", "1", "--cache", os.path.join(self.tmp, "cache"),
                        "--out", results], check=True, capture_output=True)
        r = self.plot(results, "--external", os.path.join(self.tmp, "no_such_folder"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(results, "fig10_distance_families.png")) > 0)
        with open(os.path.join(results, "fig10_distance_families_plot.json")) as f:
            doc = json.load(f)
        self.assertEqual(doc["families"], ["36h11", "16h5"])
        self.assertEqual(doc["inputs"], ["fig10_distance_summary.csv", "fig10_distance_16h5_summary.csv"])
        self.assertIn("ours (default profile), full resolution", doc["legend"])

    def test_a_broken_external_csv_is_refused_in_one_line(self):
        src = os.path.join(self.tmp, "broken_external")
        os.makedirs(src, exist_ok=True)
        with open(os.path.join(src, FILES[1]), "w") as f:
            f.write("detector,setting,distance_m,frames\njava-apriltag1,defaults,2,50\n")
        results = self.results_copy("broken")
        r = self.plot(results, "--external", src)
        self.assertNotEqual(r.returncode, 0)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn(FILES[1], r.stderr)
        self.assertIn("right_id", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(results, "external", FILES[1])))
        self.assertFalse(os.path.exists(os.path.join(results, "fig10_distance_plot.json")))
        self.assertFalse(os.path.exists(os.path.join(results, "fig10_distance.png")))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])

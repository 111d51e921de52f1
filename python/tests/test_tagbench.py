"""The Python module `tagbench` (python/module.cpp, families.cpp), run by ctest with Debian's python3
against the build tree (test_python_build_tree) and against an install in a temporary prefix
(test_python_installed). TAGBENCH_EXPECT_MODULE_DIR, when set, is where `tagbench` must come from."""
import os
import sys
import threading
import time
import unittest

import numpy as np

import tagbench


def expected_corners(family, px_per_cell, margin):
    """Where render() puts the black square's corners TL, TR, BR, BL (pixel centres at integers)."""
    n = tagbench.Family(family).payload_width + 4
    lo = margin + px_per_cell - 0.5
    hi = margin + (n - 1) * px_per_cell - 0.5
    return np.array([[lo, lo], [hi, lo], [hi, hi], [lo, hi]])


class ModuleTest(unittest.TestCase):
    def test_comes_from_the_expected_place(self):
        want = os.environ.get("TAGBENCH_EXPECT_MODULE_DIR")
        if want:
            self.assertEqual(os.path.dirname(os.path.realpath(tagbench.__file__)), os.path.realpath(want))
        self.assertRegex(tagbench.__version__, r"^\d+\.\d+\.\d+$")


class DetectTest(unittest.TestCase):
    def test_rendered_tag_id_and_corners(self):
        for family, tag_id in (("36h11", 7), ("16h5", 29)):
            img = tagbench.render_tag(family, tag_id, px_per_cell=12, margin=25)
            self.assertEqual(img.dtype, np.uint8)
            for profile in ("default", "thorough", "paper"):
                found = tagbench.Detector(families=[family], profile=profile).detect(img)
                self.assertEqual(len(found), 1, profile)
                np.testing.assert_allclose(found[0].corners, expected_corners(family, 12, 25), atol=0.25)
            found = tagbench.Detector(families=[family]).detect(img)
            self.assertEqual(len(found), 1)
            d = found[0]
            self.assertEqual((d.family, d.id, d.hamming), (family, tag_id, 0))
            self.assertEqual(d.corners.shape, (4, 2))
            np.testing.assert_allclose(d.corners, expected_corners(family, 12, 25), atol=0.25)
            np.testing.assert_allclose(d.center, d.corners.mean(axis=0), atol=0.25)
            self.assertGreater(d.decision_margin, 0.5)
            self.assertIsNone(d.pose)
            # The homography maps the tag square's (-1, -1) to the top-left corner.
            p = d.homography @ np.array([-1.0, -1.0, 1.0])
            np.testing.assert_allclose(p[:2] / p[2], d.corners[0], atol=1e-6)

    def test_row_stride_view_is_read_in_place(self):
        img = tagbench.render_tag("36h11", 3, px_per_cell=10, margin=20)
        wide = np.full((img.shape[0], img.shape[1] + 17), 255, np.uint8)
        wide[:, : img.shape[1]] = img
        view = wide[:, : img.shape[1]]
        self.assertFalse(view.flags.c_contiguous)
        det = tagbench.Detector()
        a, b = det.detect(img), det.detect(view)
        self.assertEqual([d.id for d in b], [3])
        np.testing.assert_array_equal(a[0].corners, b[0].corners)

    def test_wrong_arrays_are_value_errors(self):
        det = tagbench.Detector()
        img = tagbench.render_tag("36h11", 0, px_per_cell=4)
        for bad, words in ((img.astype(np.float32), "uint8"), (img[None], "2-D"), (np.asfortranarray(img[:, :-1]), "contiguous"),
                           (img[:, ::2], "contiguous"), (np.zeros((0, 5), np.uint8), "empty")):
            with self.assertRaises(ValueError) as cm:
                det.detect(bad)
            self.assertIn(words, str(cm.exception))
            self.assertNotIn("\n", str(cm.exception))

    def test_options_are_validated(self):
        for kwargs, words in (({"max_hamming": 11}, "max_hamming = 11"), ({"families": ["nope"]}, "unknown family"),
                              ({"camera": (0, 500, 10, 10), "tag_size": 0.1}, "camera"),
                              ({"min_decision_margin": 2}, "min_decision_margin"), ({"profile": "fast"}, "profile"),
                              # as the command line: a pose needs both, and the camera's bounds
                              ({"tag_size": 1.0}, "tag_size: given without camera"),
                              ({"camera": (500, 500, 10, 10)}, "camera: poses need tag_size"),
                              ({"camera": (500, 500, -1, 10), "tag_size": 0.1}, "camera.cx = -1"),
                              ({"input_gamma": 0}, "input_gamma")):
            with self.assertRaises(ValueError) as cm:
                tagbench.Detector(**kwargs)
            self.assertIn(words, str(cm.exception))
            self.assertNotIn("\n", str(cm.exception))

    def test_input_gamma_moves_corners_not_detections(self):
        # A linear render read as linear (1) or as camera-encoded (2.2): the same tag, corners a little apart.
        img = tagbench.render_tag("36h11", 3, px_per_cell=4, margin=8)
        a = tagbench.Detector(input_gamma=1).detect(img)
        b = tagbench.Detector(input_gamma=2.2).detect(img)
        self.assertEqual([d.id for d in a], [3])
        self.assertEqual([d.id for d in b], [3])
        np.testing.assert_allclose(a[0].corners, b[0].corners, atol=0.5)
        # The default takes the image as it is (input_gamma 1: a wrong gamma costs more than the right one
        # gains): on a blurred copy, where the two gammas place the sides apart, it gives gamma 1's corners.
        f = img.astype(np.float64)
        for _ in range(3):  # a 3 x 3 box filter, three times (about a Gaussian of 1.4 px)
            p = np.pad(f, 1, mode="edge")
            f = sum(p[1 + dy:1 + dy + f.shape[0], 1 + dx:1 + dx + f.shape[1]] for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9
        blurred = np.round(f).astype(np.uint8)
        one = tagbench.Detector(input_gamma=1).detect(blurred)
        two = tagbench.Detector(input_gamma=2.2).detect(blurred)
        default = tagbench.Detector().detect(blurred)
        self.assertEqual([d.id for d in default], [3])
        self.assertGreater(np.abs(one[0].corners - two[0].corners).max(), 0.01)
        np.testing.assert_array_equal(default[0].corners, one[0].corners)

    def test_bits_corrected_follow_the_profile_unless_given(self):
        # None keeps the profile's bits (default: by family, at most (h - 1) / 3); K means K for every family.
        d = tagbench.Detector()
        self.assertEqual((d.max_hamming, d.hamming_by_family), (3, True))
        d = tagbench.Detector(max_hamming=1)
        self.assertEqual((d.max_hamming, d.hamming_by_family), (1, False))
        d = tagbench.Detector(profile="paper")
        self.assertEqual((d.max_hamming, d.hamming_by_family), (1, False))
        # Three payload bits flipped: the default profile corrects them for 36h11, one bit everywhere does not.
        img = tagbench.render_tag("36h11", 5, px_per_cell=8, margin=16)
        k = 8
        for cell in ((2, 2), (4, 5), (6, 3)):  # payload cells (inside the 1-cell black border and white ring)
            x0, y0 = 16 + (cell[0] + 1) * k, 16 + (cell[1] + 1) * k
            img[y0 + 2:y0 + k - 2, x0 + 2:x0 + k - 2] = 255 - img[y0 + 2:y0 + k - 2, x0 + 2:x0 + k - 2]
        found = [(t.id, t.hamming) for t in tagbench.Detector().detect(img)]
        self.assertEqual(found, [(5, 3)])
        self.assertEqual(tagbench.Detector(max_hamming=1).detect(img), [])

    def test_pose_of_a_frontal_tag(self):
        k, margin, f, size = 10, 40, 600.0, 0.2
        img = tagbench.render_tag("36h11", 11, px_per_cell=k, margin=margin)
        c = (img.shape[1] - 1) / 2
        d = tagbench.Detector(camera=(f, f, c, c), tag_size=size).detect(img)[0]
        self.assertIsNotNone(d.pose)
        R, t = d.pose.R, d.pose.t
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-9)
        # The black square is 8 cells of k pixels: at distance z it spans f * size / z pixels.
        np.testing.assert_allclose(t, [0, 0, f * size / (8 * k)], atol=2e-3)
        np.testing.assert_allclose(np.abs(np.diag(R)), [1, 1, 1], atol=1e-2)
        self.assertLess(d.pose.error, 0.5)

    def test_gil_is_released_during_detection(self):
        # Another Python thread must keep running while detect() runs. With the GIL held through the
        # C++ call it could not run at all in that time: its clock readings would show one gap about
        # as long as the call. Released, the gaps are scheduling slices, a small part of the call.
        tags = [tagbench.render_tag("36h11", i, px_per_cell=20, margin=30) for i in range(16)]
        img = np.tile(np.block([tags[4 * r: 4 * r + 4] for r in range(4)]), (1, 2))  # 1040 x 2080
        det = tagbench.Detector()
        span = {}

        def work():
            span["start"] = time.perf_counter()
            span["found"] = det.detect(img)
            span["end"] = time.perf_counter()

        worker = threading.Thread(target=work)
        ticks = []
        worker.start()
        while worker.is_alive():
            ticks.append(time.perf_counter())
        worker.join()
        self.assertEqual(len(span["found"]), 32)
        took = span["end"] - span["start"]
        inside = [span["start"]] + [t for t in ticks if span["start"] < t < span["end"]] + [span["end"]]
        longest = max(b - a for a, b in zip(inside, inside[1:]))
        self.assertLess(longest, 0.5 * took, f"the other thread stood still {longest:.3f} s of the call's {took:.3f} s")


class FamilyTest(unittest.TestCase):
    def test_names_codes_decode(self):
        self.assertIn("36h11", tagbench.family_names())
        fam = tagbench.Family("36h11")
        self.assertEqual((fam.name, fam.bits, fam.payload_width, fam.min_hamming, len(fam)), ("36h11", 36, 6, 11, 587))
        code = fam.codes[42]
        self.assertEqual(fam.decode(code), (42, 0, 0))
        self.assertEqual(fam.decode(code ^ (1 << 5), max_hamming=1), (42, 1, 0))
        self.assertIsNone(fam.decode(code ^ 0b111, max_hamming=2))
        with self.assertRaises(ValueError):  # a bit above the family's 36: not one of its words
            fam.decode(code | (1 << 36))

    def test_render(self):
        img = tagbench.Family("16h5").render(0, px_per_cell=3, margin=2)
        self.assertEqual(img.shape, (8 * 3 + 4, 8 * 3 + 4))
        self.assertEqual(img[0, 0], 255)      # margin and white ring
        self.assertEqual(img[2 + 3, 2 + 3], 0)  # the black ring
        with self.assertRaises(IndexError):
            tagbench.render_tag("16h5", 30)
        with self.assertRaises(ValueError):
            tagbench.Family("no-such-family")


if __name__ == "__main__":
    unittest.main(verbosity=1)

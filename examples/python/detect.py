#!/usr/bin/env python3
"""Detects AprilTags in image files with the `tagbench` Python module and prints JSON:
    detect.py [--family F]... [--max-hamming K] [--camera fx,fy,cx,cy --tag-size M] IMAGE...
{"images": [{"input": path, "width": W, "height": H, "detections": [{"family", "id", "hamming",
 "decision_margin", "corners": [[x, y] x4: TL, TR, BR, BL], "center": [x, y], "homography": 3x3,
 "pose": {"R", "t", "error"} or null}]}]}
Images are read with Pillow (Debian's python3-pil) and reduced to gray (ITU-R 601 weights).
A bad option or an unreadable image: one line on stderr, exit 1, nothing on stdout."""
import argparse
import json
import sys

import numpy as np
from PIL import Image

import tagbench


def pose_json(p):
    return None if p is None else {"R": p.R.tolist(), "t": p.t.tolist(), "error": p.error}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("images", nargs="+")
    ap.add_argument("--family", action="append", help="family name or .fam file (repeatable; default 36h11)")
    ap.add_argument("--max-hamming", type=int, default=1)
    ap.add_argument("--camera", help="fx,fy,cx,cy in pixels (with --tag-size: poses)")
    ap.add_argument("--tag-size", type=float, help="edge of the black square, metres")
    a = ap.parse_args()
    try:
        camera = None if a.camera is None else tuple(float(v) for v in a.camera.split(","))
        if camera is not None and len(camera) != 4:
            raise ValueError(f"--camera {a.camera}: expected fx,fy,cx,cy")
        detector = tagbench.Detector(families=a.family or ["36h11"], max_hamming=a.max_hamming,
                                     camera=camera, tag_size=a.tag_size)
        images = []
        for path in a.images:
            try:
                gray = np.asarray(Image.open(path).convert("L"))
            except OSError as e:
                raise ValueError(f"{path}: cannot read the image ({e.__class__.__name__})") from None
            images.append({"input": path, "width": gray.shape[1], "height": gray.shape[0], "detections": [
                {"family": d.family, "id": d.id, "hamming": d.hamming, "decision_margin": d.decision_margin,
                 "corners": d.corners.tolist(), "center": d.center.tolist(), "homography": d.homography.tolist(),
                 "pose": pose_json(d.pose)} for d in detector.detect(gray)]})
    except ValueError as e:
        print(f"detect.py: {e}", file=sys.stderr)
        return 1
    json.dump({"images": images}, sys.stdout, indent=1)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""An example external detector for tagbench's experiments and scorer: OpenCV's aruco (Debian
python3-opencv) run as the built-in `aruco` comparator runs it (DICT_APRILTAG_36h11,
CORNER_REFINE_APRILTAG, its other defaults; pose by solvePnP SOLVEPNP_IPPE_SQUARE on its marker
corners, as estimatePoseSingleMarkers), its output converted into tagbench's conventions.

The protocol (README "Benchmark your own detector"): image paths on stdin, one a line; one JSON line
per image on stdout, any order:
  {"image": PATH, "ms": t, "detections": [{"family", "id", "corners": [[x, y] x4], "pose": {"R", "t"}}]}
or {"image": PATH, "error": message} for an image it cannot read.

The conversions (bench/raytrace/comparators.hpp proves each on ray-traced frames):
  corners  CORNER_REFINE_APRILTAG gives them with pixel i covering [i, i+1): minus 0.5; its AprilTag
           dictionaries hold the official tags turned 180 degrees, so its corner 0 is the printed
           bottom-right: ours are c[2], c[3], c[0], c[1];
  pose     its marker frame is x right, y up, z out of the face of its (turned) marker:
           R_ours = R_aruco diag(-1, 1, -1), t unchanged.

Usage, e.g.:
  tagbench raytrace angle --detectors "aruco,external:aruco-py=/usr/bin/python3 examples/external/aruco_detector.py --camera 400,400,199.5,199.5 --tag-size 0.166"
Options: --family 36h11|36h10|25h9|16h5 (default 36h11), --camera fx,fy,cx,cy with --tag-size M (pose),
--distortion k1,k2,p1,p2,k3 (OpenCV's model, given to solvePnP as the built-in comparator does under
the distortion condition and in the sixdof sweep; needs --camera)."""
import json
import sys
import time

import cv2
import numpy as np

DICTS = {"16h5": cv2.aruco.DICT_APRILTAG_16h5, "25h9": cv2.aruco.DICT_APRILTAG_25h9,
         "36h10": cv2.aruco.DICT_APRILTAG_36h10, "36h11": cv2.aruco.DICT_APRILTAG_36h11}
FLIP = np.diag([-1.0, 1.0, -1.0])


def options(argv):
    opts = {"family": "36h11", "camera": None, "tag_size": None, "distortion": None}
    i = 0
    while i < len(argv):
        if argv[i] not in ("--family", "--camera", "--tag-size", "--distortion") or i + 1 >= len(argv):
            sys.exit(f"aruco_detector.py: unknown option or missing value: {argv[i]}")
        key, value = argv[i][2:].replace("-", "_"), argv[i + 1]
        try:
            opts[key] = [float(v) for v in value.split(",")] if key in ("camera", "distortion") else (
                float(value) if key == "tag_size" else value)
        except ValueError:
            sys.exit(f"aruco_detector.py: {argv[i]} {value}: not a number or list of numbers")
        i += 2
    if opts["family"] not in DICTS:
        sys.exit(f"aruco_detector.py: --family {opts['family']}: one of {', '.join(DICTS)}")
    if (opts["camera"] is None) != (opts["tag_size"] is None):
        sys.exit("aruco_detector.py: --camera and --tag-size go together")
    if opts["camera"] is not None and len(opts["camera"]) != 4:
        sys.exit("aruco_detector.py: --camera wants fx,fy,cx,cy")
    if opts["distortion"] is not None and (opts["camera"] is None or len(opts["distortion"]) != 5):
        sys.exit("aruco_detector.py: --distortion wants k1,k2,p1,p2,k3 and --camera")
    return opts


def main():
    opts = options(sys.argv[1:])
    cv2.setNumThreads(1)
    dictionary = cv2.aruco.getPredefinedDictionary(DICTS[opts["family"]])
    params = cv2.aruco.DetectorParameters_create()
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_APRILTAG
    camera = None
    dist = None if opts["distortion"] is None else np.array(opts["distortion"], dtype=np.float64).reshape(1, 5)
    if opts["camera"]:
        fx, fy, cx, cy = opts["camera"]
        camera = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]], dtype=np.float64)
        h = np.float32(opts["tag_size"] / 2)
        # Its marker's corners in its frame, as estimatePoseSingleMarkers has them (float, as the C++ comparator).
        obj = np.array([[-h, h, 0], [h, h, 0], [h, -h, 0], [-h, -h, 0]], dtype=np.float32)
    for line in sys.stdin:
        path = line.rstrip("\n")
        if not path:
            continue
        image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
        if image is None:
            print(json.dumps({"image": path, "error": "cannot read the image"}), flush=True)
            continue
        t0 = time.perf_counter()
        corners, ids, _ = cv2.aruco.detectMarkers(image, dictionary, parameters=params)
        found = []
        for k in range(0 if ids is None else len(ids)):
            centred = (corners[k].reshape(4, 2) - np.float32(0.5)).astype(np.float32)
            det = {"family": opts["family"], "id": int(ids[k][0]),
                   "corners": [[float(x), float(y)] for x, y in (centred[(j + 2) % 4] for j in range(4))]}
            if camera is not None:
                ok, rvec, tvec = cv2.solvePnP(obj, centred, camera, dist, flags=cv2.SOLVEPNP_IPPE_SQUARE)
                if ok:
                    rot, _ = cv2.Rodrigues(rvec)
                    r = rot @ FLIP
                    if np.all(np.isfinite(r)) and np.all(np.isfinite(tvec)):
                        det["pose"] = {"R": r.tolist(), "t": [float(v) for v in tvec.reshape(3)]}
            found.append(det)
        ms = (time.perf_counter() - t0) * 1000
        print(json.dumps({"image": path, "ms": ms, "detections": found}), flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Turns bench_detector's Google Benchmark JSON into results/speed_stages.csv: one row per detector, mode and
resolution (milliseconds per frame, single thread), our per-stage times, and the ratio of ours to
libapriltag at the matching setting (full resolution vs decimate 1, half vs decimate 2).
Usage: speed_to_csv.py REPORT.json OUT.csv   (OUT written atomically)"""
import csv
import json
import os
import re
import sys

STAGES = ["blur_ms", "gradient_ms", "segmentation_ms", "line_fit_ms", "quads_ms", "decode_ms"]


def main():
    report, out = sys.argv[1], sys.argv[2]
    data = json.load(open(report))
    cpu = os.environ.get("TAGBENCH_CPU", "")
    rows = []
    for b in data["benchmarks"]:
        m = re.match(r"BM_(\w+)/w:(\d+)/h:(\d+)/(\w+):(\d+)", b["name"])
        if not m:
            continue
        kind, w, h, arg, val = m.groups()
        ms = b["real_time"] if b["time_unit"] == "ms" else b["real_time"] / 1e6
        if kind == "Ours":
            det, mode = "tagbench", {"0": "full-resolution", "1": "half-resolution",
                                     "2": "full-resolution, 2012 close-enough rule"}[val]
        elif kind == "AprilTag3":
            det, mode = "libapriltag-3.3", f"decimate-{val}"
        else:
            det, mode = "opencv-aruco-4.6", "CORNER_REFINE_APRILTAG"
        row = {"detector": det, "mode": mode, "width": int(w), "height": int(h), "ms_per_frame": ms,
               "frames_per_second": 1000.0 / ms, "detections": int(b.get("detections", 0)), "threads": 1,
               "family": "36h11", "scene": "make_scene(seed 1234, 6 tags)", "cpu": cpu}
        for s in STAGES + ["segments", "candidate_quads"]:
            row[s] = int(b[s]) if s in ("segments", "candidate_quads") and s in b else b.get(s, "")
        rows.append(row)
    ref = {(r["width"], r["mode"]): r["ms_per_frame"] for r in rows if r["detector"] == "libapriltag-3.3"}
    for r in rows:
        if r["detector"] == "tagbench":
            key = (r["width"], "decimate-2" if r["mode"] == "half-resolution" else "decimate-1")
            r["ratio_to_libapriltag"] = r["ms_per_frame"] / ref[key] if key in ref else ""
            r["ratio_reference"] = f"libapriltag-3.3 {key[1]}"
        else:
            r["ratio_to_libapriltag"] = ""
            r["ratio_reference"] = ""
    cols = ["detector", "mode", "width", "height", "ms_per_frame", "frames_per_second", "detections",
            "ratio_to_libapriltag", "ratio_reference"] + STAGES + ["segments", "candidate_quads", "threads", "family", "scene", "cpu"]
    tmp = out + ".tmp"
    with open(tmp, "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=cols)
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(tmp, out)


if __name__ == "__main__":
    main()

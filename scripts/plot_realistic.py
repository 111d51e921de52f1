#!/usr/bin/python3
"""Plots `tagbench realistic` (the realistic image set, issue 17) from realistic_summary.csv and its
JSON sidecar: realistic.png, detection rate against the black square's size bin (one line per
detector, the Wilson 95 % interval shaded) and the median corner RMS of the detected tags.
Usage: plot_realistic.py RESULTS_DIR. The PNG is written to a temporary and renamed."""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_common import STYLE, save  # noqa: E402


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    path = os.path.join(results, "realistic_summary.csv")
    try:
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["size_bin"] != "all"]
        with open(os.path.join(results, "realistic.json")) as f:
            meta = json.load(f)
    except FileNotFoundError as e:
        sys.exit(f"plot_realistic.py: {e.filename}: missing (run tagbench realistic)")
    bins = []
    for r in rows:
        if r["size_bin"] not in bins:
            bins.append(r["size_bin"])
    detectors = []
    for r in rows:
        if r["detector"] not in detectors:
            detectors.append(r["detector"])
    x = list(range(len(bins)))
    fig, (ax_rate, ax_err) = plt.subplots(1, 2, figsize=(12, 4.8))
    for i, d in enumerate(detectors):
        label, colour, style = STYLE.get(d, (d, f"C{i}", "-"))
        by_bin = {r["size_bin"]: r for r in rows if r["detector"] == d}
        num = lambda b, k: float(by_bin[b][k]) if by_bin.get(b) and by_bin[b][k] != "" else float("nan")  # noqa: E731
        ax_rate.plot(x, [num(b, "detection_rate") for b in bins], style, color=colour, marker="o", label=label)
        ax_rate.fill_between(x, [num(b, "rate_lo95") for b in bins], [num(b, "rate_hi95") for b in bins],
                             color=colour, alpha=0.12)
        ax_err.plot(x, [num(b, "corner_rms_px_median") for b in bins], style, color=colour, marker="o", label=label)
    tags = {r["size_bin"]: r["tags"] for r in rows}
    for ax in (ax_rate, ax_err):
        ax.set_xticks(x)
        ax.set_xticklabels([f"{b}\n({tags[b]} tags)" for b in bins])
        ax.set_xlabel("black square, px (sqrt of its area in the image)")
        ax.grid(alpha=0.3)
    ax_rate.set_ylabel("detection rate (Wilson 95 % interval)")
    ax_rate.set_ylim(-0.02, 1.02)
    ax_err.set_ylabel("median corner RMS of detected tags (px)")
    ax_err.set_ylim(bottom=0)
    ax_rate.legend(fontsize=8, loc="lower right")
    s = meta["settings"]
    fig.suptitle(f"Realistic set: {s['frames']} frames {s['width']}x{s['height']}, {meta['tags']} {s['family']} tags, "
                 f"tilt 0-{s['max_tilt_deg']:g} deg, blur sigma {s['blur_sigma_px'][0]:g}-{s['blur_sigma_px'][1]:g} px, "
                 f"JPEG q {s['jpeg_quality'][0]:g}-{s['jpeg_quality'][1]:g}, seed {s['seed']}", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(results, "realistic.png"))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plots the 6-DoF sweep written by `tagbench raytrace sixdof` (or `tagbench score` on a sixdof dataset)
from sixdof_summary.csv and sixdof.json: sixdof.png, a grid whose rows are the outcomes (detection rate
with its Wilson 95 % interval shaded, median corner RMS, median orientation error, median distance
error; medians over the frames detected in the bin, drawn where at least 3 were) and whose columns are
the six pose variables (distance, phi, tilt axis, roll, image x, image y), each binned over its range as
the summary bins it; one colour per detector (plot_common.py's styles), so one sees which variable
breaks which detector. A sidecar, sixdof_plot.json, names the inputs and the legend.

Usage: plot_sixdof.py RESULTS_DIR. The PNG and the sidecar are written to temporaries and renamed."""
import csv
import json
import os
import sys

from plot_common import MIN_DETECTED_FOR_ERRORS, detectors_in, number, plt, save, style

POSE = [  # column, x label
    ("distance_m", "distance (m)"),
    ("phi_deg", "phi: tag normal vs direction to camera (deg)"),
    ("tilt_axis_deg", "tilt axis (deg)"),
    ("roll_deg", "roll, in-plane rotation (deg)"),
    ("image_x", "tag centre, image x (px)"),
    ("image_y", "tag centre, image y (px)"),
]
OUTCOMES = [  # summary column, y label, log scale
    ("detection_rate", "detection rate (%)", False),
    ("corner_rms_px", "corner RMS (px), median", True),
    ("orientation_error_deg", "orientation error (deg), median", True),
    ("distance_error_m", "distance error (m), median", True),
]


def load(results):
    try:
        with open(os.path.join(results, "sixdof_summary.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        with open(os.path.join(results, "sixdof.json")) as f:
            meta = json.load(f)
    except OSError as e:
        sys.exit(f"plot_sixdof.py: {e.filename}: {e.strerror}")
    if not rows or "variable" not in rows[0]:
        sys.exit(f"plot_sixdof.py: {results}/sixdof_summary.csv has no sixdof rows")
    return rows, meta


def bins(rows, variable, detector):
    sel = [r for r in rows if r["variable"] == variable and r["detector"] == detector]
    return sorted(sel, key=lambda r: float(r["bin_lo"]))


def centre(r):
    return (float(r["bin_lo"]) + float(r["bin_hi"])) / 2


def draw(ax, sel, outcome, detector):
    label, colour, ls = style(detector)
    if outcome == "detection_rate":
        xs = [centre(r) for r in sel]
        ax.plot(xs, [100 * float(r["detection_rate"]) for r in sel], ls, color=colour, marker="o", ms=3, label=label)
        ax.fill_between(xs, [100 * float(r["rate_lo95"]) for r in sel], [100 * float(r["rate_hi95"]) for r in sel],
                        color=colour, alpha=0.07, linewidth=0)
        return
    pts = [(centre(r), number(r[outcome + "_median"])) for r in sel
           if int(r["detected"]) >= MIN_DETECTED_FOR_ERRORS and number(r[outcome + "_median"]) == number(r[outcome + "_median"])]
    if pts:
        floor = 1e-4  # log axes: a zero error is drawn at the floor
        ax.plot([p[0] for p in pts], [max(p[1], floor) for p in pts], ls, color=colour, marker="o", ms=3, label=label)


def settings_line(meta):
    s, x = meta["settings"], meta["settings"]["sixdof"]
    lens = ", ".join(f"{k:g}" for k in x["lens"])
    return (f'{s["scene"]} scene, {s["family"]}, black square {s["tag_size_m"]:g} m, {x["frames"]} frames '
            f'(scrambled Halton, seed {s["seed"]}), distance {x["distance_range_m"][0]:g}-{x["distance_range_m"][1]:g} m, '
            f'phi 0-{x["phi_max_deg"]:g} deg; 400x400 px, f = 400 px, lens k1,k2,p1,p2,k3 = {lens}, defocus sigma '
            f'0-{x["defocus_max_px"]:g} px, noise sigma 0-{x["noise_max"]:g} levels, 8 bits')


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        sys.exit("usage: plot_sixdof.py RESULTS_DIR")
    results = sys.argv[1]
    rows, meta = load(results)
    detectors = detectors_in(rows)
    ranges = {v["name"]: (v["lo"], v["hi"]) for v in meta["settings"]["sixdof"]["variables"]}
    fig, grid = plt.subplots(len(OUTCOMES), len(POSE), figsize=(4 * len(POSE), 3.2 * len(OUTCOMES)), squeeze=False)
    for i, (outcome, ylabel, log) in enumerate(OUTCOMES):
        for k, (variable, xlabel) in enumerate(POSE):
            ax = grid[i][k]
            for d in detectors:
                draw(ax, bins(rows, variable, d), outcome, d)
            if log:
                ax.set_yscale("log")
            else:
                ax.set_ylim(-2, 102)
            ax.grid(True, alpha=0.3)
            ax.set_xlim(*ranges[variable])
            if i == len(OUTCOMES) - 1:
                ax.set_xlabel(xlabel)
            if k == 0:
                ax.set_ylabel(ylabel)
    handles, labels = grid[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=min(4, max(1, len(labels))), fontsize=9, frameon=False)
    fig.suptitle(settings_line(meta), y=0.005, va="bottom", fontsize=9)
    fig.tight_layout(rect=(0, 0.02, 1, 0.95))
    save(fig, os.path.join(results, "sixdof.png"))
    doc = {"tool": "scripts/plot_sixdof.py", "figure": "sixdof.png", "inputs": ["sixdof_summary.csv", "sixdof.json"],
           "rows": [o[0] for o in OUTCOMES], "columns": [p[0] for p in POSE], "legend": labels}
    path = os.path.join(results, "sixdof_plot.json")
    with open(path + ".tmp.json", "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    os.replace(path + ".tmp.json", path)


if __name__ == "__main__":
    main()

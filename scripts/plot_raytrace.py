#!/usr/bin/python3
"""Plots the ray-traced localization experiments written by `tagbench raytrace` (paper Figs. 9 and 10,
and the conditions beyond the paper), from the *_summary.csv files and their JSON sidecars:

  fig9_angle.png      orientation error, distance error and detection rate against phi
  fig10_distance.png  the same against distance, the black square's width in pixels on a second x-axis
  conditions.png      per condition: detection rate, and median orientation error, against strength

One line per detector: the median over the frames it detected, with the 10-90 percentile band shaded
(errors are drawn where at least 3 frames were detected); detection rates with their Wilson 95 %
interval shaded. Usage: plot_raytrace.py RESULTS_DIR [angle|distance|conditions ...] (default: every
experiment whose summary exists). Each PNG is written to a temporary and renamed."""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STEMS = {"angle": "fig9_angle", "distance": "fig10_distance", "conditions": "conditions"}
STYLE = {  # detector: (label, colour, line style)
    "tagbench-full": ("ours, full resolution", "tab:blue", "-"),
    "tagbench-half": ("ours, half resolution", "tab:cyan", "--"),
    "libapriltag-d1": ("libapriltag 3.3, decimate 1", "tab:orange", "-"),
    "libapriltag-d2": ("libapriltag 3.3, decimate 2", "tab:red", "--"),
    "aruco": ("OpenCV 4.6 aruco (APRILTAG refine)", "tab:green", "-"),
}
MIN_DETECTED_FOR_ERRORS = 3
CONDITION_LABELS = {
    "noise": "noise sigma (8-bit levels)",
    "blur": "blur sigma (px)",
    "gradient": "light lost across the tag (fraction)",
    "occlusion": "fraction of one border edge covered",
    "bent": "bend (degrees)",
    "distortion": "barrel distortion, -k1",
}


def number(s):
    return float(s) if s not in ("", None) else math.nan


def load(results, experiment):
    stem = STEMS[experiment]
    with open(os.path.join(results, stem + "_summary.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(results, stem + ".json")) as f:
        meta = json.load(f)
    if not rows:
        sys.exit(f"plot_raytrace.py: {stem}_summary.csv has no rows")
    return rows, meta


def series(rows, detector, condition=None):
    """Rows of one detector (and condition), sorted by step."""
    sel = [r for r in rows if r["detector"] == detector and (condition is None or r["condition"] == condition)]
    return sorted(sel, key=lambda r: float(r["step"]))


def detectors_in(rows):
    seen = []
    for r in rows:
        if r["detector"] not in seen:
            seen.append(r["detector"])
    return seen


def style(detector):
    return STYLE.get(detector, (detector, None, "-"))


def plot_error(ax, sel, column, detector):
    label, colour, ls = style(detector)
    pts = [(float(r["step"]), number(r[column + "_median"]), number(r[column + "_p10"]), number(r[column + "_p90"]))
           for r in sel if int(r["detected"]) >= MIN_DETECTED_FOR_ERRORS and not math.isnan(number(r[column + "_median"]))]
    if not pts:
        return
    xs = [p[0] for p in pts]
    floor = 1e-4  # log axes: a zero error is drawn at the floor
    ax.plot(xs, [max(p[1], floor) for p in pts], ls, color=colour, marker="o", ms=3, label=label)
    ax.fill_between(xs, [max(p[2], floor) for p in pts], [max(p[3], floor) for p in pts], color=colour, alpha=0.12,
                    linewidth=0)


def plot_rate(ax, sel, detector):
    label, colour, ls = style(detector)
    xs = [float(r["step"]) for r in sel]
    ax.plot(xs, [100 * float(r["detection_rate"]) for r in sel], ls, color=colour, marker="o", ms=3, label=label)
    ax.fill_between(xs, [100 * float(r["rate_lo95"]) for r in sel], [100 * float(r["rate_hi95"]) for r in sel],
                    color=colour, alpha=0.07, linewidth=0)


def settings_line(meta):
    s = meta["settings"]
    text = (f'{s["scene"]} scene, {s["family"]}, black square {s["tag_size_m"]:g} m, {s["trials"]} trials a step, '
            f'seed {s["seed"]}; 400x400 px, f = 400 px (POV-Ray)')
    if s.get("distance_m"):
        text += f', distance {s["distance_m"]:g} m'
    return text


def sweep_figure(rows, meta, experiment, out):
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2))
    xlabel = "phi (degrees)" if experiment == "angle" else "distance (m)"
    for det in detectors_in(rows):
        sel = series(rows, det)
        plot_error(axes[0], sel, "orientation_error_deg", det)
        plot_error(axes[1], sel, "distance_error_percent", det)
        plot_rate(axes[2], sel, det)
    axes[0].set_ylabel("orientation error (degrees)")
    axes[0].set_title("Orientation error (median, 10-90 % band)")
    axes[1].set_ylabel("distance error (% of the distance)")
    axes[1].set_title("Distance error (median, 10-90 % band)")
    axes[2].set_ylabel("detected with the right id (%)")
    axes[2].set_title("Detection rate (Wilson 95 % band)")
    axes[2].set_ylim(-3, 103)
    for ax in axes[:2]:
        ax.set_yscale("log")
    steps = sorted({float(r["step"]) for r in rows})
    for ax in axes:
        ax.set_xlabel(xlabel)
        ax.grid(True, which="both", alpha=0.3)
        if experiment == "angle":
            ax.set_xlim(min(steps + [0]) - 1, max(steps) + 2)
        else:  # no zero on a distance axis: the pixel axis is its reciprocal
            ax.set_xlim(max(0.5, min(steps) - 1), max(steps) * 1.02 + 0.5)
    if experiment == "distance":
        size = meta["settings"]["tag_size_m"]
        f = meta["camera"]["fx"]

        def to_px(d):
            import numpy as np
            d = np.asarray(d, dtype=float)
            return np.where(d > 1e-9, f * size / np.maximum(d, 1e-9), np.inf)

        ticks = [t for t in (200, 50, 30, 20, 15, 12, 10, 8, 7) if min(steps) <= f * size / t <= max(steps) * 1.05]
        for ax in axes:
            top = ax.secondary_xaxis("top", functions=(to_px, to_px))
            top.set_ticks(ticks)
            top.set_xlabel("black square width (px), face-on")
    axes[2].legend(fontsize=8, loc="lower left")
    title = ("Fig. 9 reproduced: localization against phi, the angle between the tag's normal and the direction "
             "to the camera" if experiment == "angle"
             else "Fig. 10 reproduced: localization against distance")
    fig.suptitle(title + "\n" + settings_line(meta), fontsize=10)
    fig.tight_layout()
    save(fig, out)


def conditions_figure(rows, meta, out):
    conditions = []
    for r in rows:
        if r["condition"] not in conditions:
            conditions.append(r["condition"])
    units = {c["name"]: c["unit"] for c in meta.get("conditions", [])}
    cols = min(3, len(conditions))
    blocks = math.ceil(len(conditions) / cols)
    fig, axes = plt.subplots(2 * blocks, cols, figsize=(5.4 * cols, 6.4 * blocks), squeeze=False)
    for i, cond in enumerate(conditions):
        rate_ax, err_ax = axes[2 * (i // cols)][i % cols], axes[2 * (i // cols) + 1][i % cols]
        for det in detectors_in(rows):
            sel = series(rows, det, cond)
            plot_rate(rate_ax, sel, det)
            plot_error(err_ax, sel, "orientation_error_deg", det)
        rate_ax.set_title(f"{cond}: detection rate")
        rate_ax.set_ylabel("detected (%)")
        rate_ax.set_ylim(-3, 103)
        err_ax.set_title(f"{cond}: orientation error (median, 10-90 %)")
        err_ax.set_ylabel("degrees")
        err_ax.set_yscale("log")
        for ax in (rate_ax, err_ax):
            ax.set_xlabel(CONDITION_LABELS.get(cond, units.get(cond, "strength")))
            ax.grid(True, which="both", alpha=0.3)
    for j in range(len(conditions), blocks * cols):
        axes[2 * (j // cols)][j % cols].axis("off")
        axes[2 * (j // cols) + 1][j % cols].axis("off")
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Beyond the paper: the same frames under noise, blur, lighting, occlusion, bending and lens "
                 "distortion (strength 0 = the plain frame)\n" + settings_line(meta), fontsize=10)
    fig.tight_layout()
    save(fig, out)


def save(fig, out):
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    os.replace(tmp, out)


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    wanted = sys.argv[2:]
    for w in wanted:
        if w not in STEMS:
            sys.exit(f"plot_raytrace.py: unknown experiment '{w}' (angle, distance, conditions)")
    if not wanted:
        wanted = [e for e, stem in STEMS.items() if os.path.exists(os.path.join(results, stem + "_summary.csv"))]
        if not wanted:
            sys.exit(f"plot_raytrace.py: no *_summary.csv of tagbench raytrace in {results}")
    for experiment in wanted:
        try:
            rows, meta = load(results, experiment)
        except FileNotFoundError as e:
            sys.exit(f"plot_raytrace.py: {e.filename}: missing (run tagbench raytrace {experiment})")
        out = os.path.join(results, STEMS[experiment] + ".png")
        if experiment == "conditions":
            conditions_figure(rows, meta, out)
        else:
            sweep_figure(rows, meta, experiment, out)


if __name__ == "__main__":
    main()

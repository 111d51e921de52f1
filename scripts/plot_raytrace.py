#!/usr/bin/python3
"""Plots the ray-traced localization experiments written by `tagbench raytrace` (paper Figs. 9 and 10,
and the conditions beyond the paper), from the *_summary.csv files and their JSON sidecars:

  fig9_angle.png      orientation error, distance error and detection rate against phi
  fig10_distance.png  the same against distance, the black square's width in pixels on a second x-axis
  conditions.png      per condition: detection rate, and median orientation error, against strength
  fig10_distance_families.png  with distance, when the 16h5 / 25h9 distance sweeps are there too
                      (fig10_distance_16h5_summary.csv, ..._25h9_...): the detection rate against
                      distance, a panel per family, 36h11 first; sidecar fig10_distance_families_plot.json

One line per detector: the median over the frames it detected, with the 10-90 percentile band shaded
(errors are drawn where at least 3 frames were detected); detection rates with their Wilson 95 %
interval shaded.

Figs. 9 and 10 also draw the paper's own detector (Java AprilTag 1) and its comparator (ARToolKitPlus),
run outside the build on the frames `make bench` renders (GPL code the project cannot ship; see
../shared/reference/external_runs/README.md). Their CSVs are read from --external DIR (default: the
folder shared/reference/external_runs beside the clone) and copied into RESULTS_DIR/external/, so a
clone without that folder still plots them from there; they are drawn with a long-dash line and x
markers, labelled "run outside the build", and carry per-step medians only (no bands). Each figure's
sidecar, <stem>_plot.json, names the files it used and the legend entries it drew.

Usage: plot_raytrace.py RESULTS_DIR [--external DIR] [angle|distance|conditions ...] (default: every
experiment whose summary exists). Each PNG, CSV copy and sidecar is written to a temporary and renamed."""
import csv
import hashlib
import json
import math
import os
import shutil
import sys

from plot_common import MIN_DETECTED_FOR_ERRORS, detectors_in, number, plt, save, style

STEMS = {"angle": "fig9_angle", "distance": "fig10_distance", "conditions": "conditions"}
DEFAULT_EXTERNAL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "reference",
                                "external_runs")
# experiment: (file, setting, label, colour) per curve; the step column of each experiment.
EXTERNAL = {
    "angle": [
        ("artoolkitplus_fig9_angle.csv", "full-autoseq",
         "ARToolKitPlus (BCH, full res., auto threshold; run outside the build)", "saddlebrown"),
        ("artoolkitplus_fig9_angle.csv", "half-fixed100",
         "ARToolKitPlus as shipped (BCH, half res.; run outside the build)", "tab:pink"),
    ],
    "distance": [
        ("java_apriltag1_fig10_distance.csv", "defaults",
         "Java AprilTag 1 (paper's code, defaults; run outside the build)", "black"),
        ("artoolkitplus_fig10_distance.csv", "full-autoseq",
         "ARToolKitPlus (BCH, full res., auto threshold; run outside the build)", "saddlebrown"),
        ("artoolkitplus_fig10_distance.csv", "half-fixed100",
         "ARToolKitPlus as shipped (BCH, half res.; run outside the build)", "tab:pink"),
    ],
}
EXTERNAL_STEP = {"angle": "phi_deg", "distance": "distance_m"}
EXTERNAL_REQUIRED = ("detector", "setting", "frames", "right_id", "detection_rate")
EXTERNAL_LINE = (0, (7, 3))  # long dashes: none of our detectors uses them
# The external runs were made on the frames of `make bench`: these settings and the same steps.
EXTERNAL_FRAMES = {"scene": "plain", "family": "36h11", "seed": 1, "trials": 50}
CONDITION_LABELS = {
    "noise": "noise sigma (8-bit levels)",
    "blur": "blur sigma (px)",
    "gradient": "light lost across the tag (fraction)",
    "occlusion": "fraction of one border edge covered",
    "bent": "bend (degrees)",
    "distortion": "barrel distortion, -k1",
}


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


def plot_external(axes, curve):
    """A run made outside the build: per-step medians (no bands), long dashes and x markers."""
    label, colour, pts = curve["label"], curve["colour"], curve["points"]
    kw = dict(color=colour, ls=EXTERNAL_LINE, marker="x", ms=4, lw=1.4)
    for ax, column in zip(axes[:3], ("orientation_error_deg_median", "distance_error_percent_median",
                                     "corner_rms_px_median")):
        sel = [(x, number(r.get(column))) for x, r in pts if int(r["right_id"]) >= MIN_DETECTED_FOR_ERRORS]
        sel = [(x, max(v, 1e-4)) for x, v in sel if not math.isnan(v)]
        if sel:
            ax.plot([p[0] for p in sel], [p[1] for p in sel], label=label, **kw)
    axes[3].plot([x for x, _ in pts], [100 * float(r["detection_rate"]) for _, r in pts], label=label, **kw)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def copy_atomic(src, dst):
    os.makedirs(os.path.dirname(dst), exist_ok=True)
    tmp = dst + ".tmp.csv"
    shutil.copyfile(src, tmp)
    os.replace(tmp, dst)


def read_external(path, step_column):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in EXTERNAL_REQUIRED + (step_column,) if c not in (reader.fieldnames or [])]
        if missing:
            sys.exit(f"plot_raytrace.py: {path}: no column {missing[0]} (an external run's CSV)")
        rows = list(reader)
    if not rows:
        sys.exit(f"plot_raytrace.py: {path}: no rows")
    for r in rows:
        try:
            float(r[step_column]), int(r["right_id"]), float(r["detection_rate"])
        except ValueError:
            sys.exit(f"plot_raytrace.py: {path}: a row with a non-numeric {step_column}, right_id or "
                     "detection_rate")
    return rows


def external_curves(results, experiment, source_dir, meta):
    """The external runs for this figure: each file is taken from source_dir when it is there (and
    copied into results/external/), else from results/external/; returns (curves, sidecar entries)."""
    curves, used = [], []
    steps = sorted(float(x) for x in meta["settings"]["steps"])
    same_settings = all(meta["settings"].get(k) == v for k, v in EXTERNAL_FRAMES.items())
    for name in dict.fromkeys(spec[0] for spec in EXTERNAL.get(experiment, [])):
        copy = os.path.join(results, "external", name)
        src = os.path.join(source_dir, name) if source_dir else None
        if src and os.path.isfile(src):
            read_external(src, EXTERNAL_STEP[experiment])  # checked before it replaces the copy
            copy_atomic(src, copy)
            origin = os.path.relpath(os.path.abspath(src), os.path.dirname(os.path.abspath(results)))
        elif os.path.isfile(copy):
            origin = os.path.join(os.path.basename(os.path.normpath(results)), "external", name)
        else:
            continue
        rows = read_external(copy, EXTERNAL_STEP[experiment])
        drawn = []
        for file, setting, label, colour in EXTERNAL[experiment]:
            sel = [r for r in rows if file == name and r["setting"] == setting]
            if not sel:
                continue
            pts = sorted(((float(r[EXTERNAL_STEP[experiment]]), r) for r in sel), key=lambda p: p[0])
            curves.append({"label": label, "colour": colour, "points": pts})
            drawn.append({"setting": setting, "detector": sel[0]["detector"], "label": label})
        ext_steps = sorted({float(r[EXTERNAL_STEP[experiment]]) for r in rows})
        used.append({"file": f"external/{name}", "read_from": origin, "sha256": sha256(copy), "curves": drawn,
                     "same_frames_as_this_sweep": same_settings and ext_steps == steps})
    return curves, used


def settings_line(meta):
    s = meta["settings"]
    text = (f'{s["scene"]} scene, {s["family"]}, black square {s["tag_size_m"]:g} m, {s["trials"]} trials a step, '
            f'seed {s["seed"]}; 400x400 px, f = 400 px (POV-Ray)')
    if s.get("distance_m"):
        text += f', distance {s["distance_m"]:g} m'
    return text


def sweep_figure(rows, meta, experiment, out, external):
    fig, grid = plt.subplots(2, 2, figsize=(15, 10.5))
    axes = [grid[0][0], grid[0][1], grid[1][0], grid[1][1]]
    xlabel = "phi (degrees)" if experiment == "angle" else "distance (m)"
    for det in detectors_in(rows):
        sel = series(rows, det)
        plot_error(axes[0], sel, "orientation_error_deg", det)
        plot_error(axes[1], sel, "distance_error_percent", det)
        plot_error(axes[2], sel, "corner_rms_px", det)
        plot_rate(axes[3], sel, det)
    for curve in external:
        plot_external(axes, curve)
    axes[0].set_ylabel("orientation error (degrees)")
    axes[0].set_title("Orientation error (median, 10-90 % band)")
    axes[1].set_ylabel("distance error (% of the distance)")
    axes[1].set_title("Distance error (median, 10-90 % band)")
    axes[2].set_ylabel("corner error, RMS of the four corners (px)")
    axes[2].set_title("Corner error (median, 10-90 % band)")
    axes[3].set_ylabel("detected with the right id (%)")
    axes[3].set_title("Detection rate (Wilson 95 % band)")
    axes[3].set_ylim(-3, 103)
    for ax in axes[:3]:
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
    # One legend for the four panels, below them: inside a panel it would hide the curves.
    handles, labels = axes[3].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3 if len(labels) > 5 else len(labels), fontsize=9)
    title = ("Fig. 9 reproduced: localization against phi, the angle between the tag's normal and the direction "
             "to the camera" if experiment == "angle"
             else "Fig. 10 reproduced: localization against distance")
    note = ""
    if external:
        note = ("\nLong dashes, x markers: detectors run outside the build (GPL, not shipped) on the frames "
                "`make bench` renders; per-step medians, no bands")
    fig.suptitle(title + "\n" + settings_line(meta) + note, fontsize=10)
    fig.tight_layout(rect=(0, 0.027 * math.ceil(len(labels) / 3) + 0.01, 1, 1))
    save(fig, out)
    return labels


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


SMALL_FAMILIES = ("16h5", "25h9")


def families_figure(results, rows36):
    """The detection rate against distance per family, when another family's distance sweep is there."""
    panels = [("36h11", rows36)]
    for fam in SMALL_FAMILIES:
        path = os.path.join(results, f"fig10_distance_{fam}_summary.csv")
        if os.path.exists(path):
            with open(path, newline="") as f:
                panels.append((fam, list(csv.DictReader(f))))
    if len(panels) == 1:
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.8), squeeze=False)
    legend = []
    for ax, (fam, rows) in zip(axes[0], panels):
        for det in detectors_in(rows):
            plot_rate(ax, series(rows, det), det)
            if style(det)[0] not in legend:
                legend.append(style(det)[0])
        ax.set_title(f"{fam}: detected with the right id (%)")
        ax.set_xlabel("distance (m), 1 m black square, f = 400 px")
        ax.set_ylim(-3, 103)
        ax.grid(True, alpha=0.3)
    handles = {}  # one legend for all panels: every detector any panel drew
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center", ncol=4, fontsize=8)
    save(fig, os.path.join(results, "fig10_distance_families.png"))
    doc = {"tool": "scripts/plot_raytrace.py", "figure": "fig10_distance_families.png",
           "inputs": ["fig10_distance_summary.csv"] + [f"fig10_distance_{f}_summary.csv" for f, _ in panels[1:]],
           "families": [f for f, _ in panels], "legend": legend}
    path = os.path.join(results, "fig10_distance_families_plot.json")
    with open(path + ".tmp.json", "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    os.replace(path + ".tmp.json", path)


def write_sidecar(results, experiment, meta, legend, used):
    stem = STEMS[experiment]
    doc = {"tool": "scripts/plot_raytrace.py", "figure": stem + ".png",
           "inputs": [stem + "_summary.csv", stem + ".json"],
           "external_runs": used,
           "external_note": ("runs made outside the build on the frames `make bench` renders, read from "
                             "../shared/reference/external_runs when it is there (then copied into "
                             "external/), else from external/; see that folder's README.md"),
           "legend": legend}
    path = os.path.join(results, stem + "_plot.json")
    tmp = path + ".tmp.json"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def parse_args(argv):
    results, external, wanted = None, DEFAULT_EXTERNAL, []
    i = 0
    while i < len(argv):
        if argv[i] == "--external":
            if i + 1 >= len(argv):
                sys.exit("plot_raytrace.py: --external needs a folder")
            external = argv[i + 1]
            i += 2
            continue
        if results is None:
            results = argv[i]
        else:
            wanted.append(argv[i])
        i += 1
    return results or "results", external, wanted


def main():
    results, external_dir, wanted = parse_args(sys.argv[1:])
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
            curves, used = external_curves(results, experiment, external_dir, meta)
            legend = sweep_figure(rows, meta, experiment, out, curves)
            write_sidecar(results, experiment, meta, legend, used)
            if experiment == "distance":
                families_figure(results, rows)


if __name__ == "__main__":
    main()

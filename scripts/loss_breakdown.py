#!/usr/bin/python3
"""Where the missed tags were lost (issue 17, section 2): a breakdown per step (sweeps: distance, angle,
condition strength) or size bin (realistic set) and detector, from the lost_<stage> columns of a
summary CSV (fig9_angle_summary.csv, fig10_distance_summary.csv, conditions_summary.csv,
realistic_summary.csv). Put two profiles side by side ("before/after", e.g. tagbench-paper,tagbench)
with --detectors; only detectors that can explain their misses (ours) have stages.

Usage: loss_breakdown.py SUMMARY.csv [--detectors A,B,...] [--format csv|markdown] [--out FILE]
CSV: a header row, then one row per step (or bin) and detector: the step, its unit, the detector,
frames (tags), detected, missed, then the missed count per stage (the summary's lost_* columns), and
the file it came from. Markdown: the same as a table (stages with no miss anywhere left out). Written
to --out (a temporary file, then renamed) or stdout."""
import argparse
import csv
import os
import sys
import tempfile


def fail(msg):
    sys.exit(f"loss_breakdown.py: {msg}")


def load(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    if not rows:
        fail(f"{path}: no rows")
    stages = [c for c in rows[0].keys() if c.startswith("lost_")]
    if not stages:
        fail(f"{path}: no lost_* columns (a summary written before the loss stages, or not a summary)")
    return rows, stages


def breakdown(rows, stages, detectors):
    realistic = "size_bin" in rows[0]
    out = []
    for r in rows:
        if detectors and r["detector"] not in detectors:
            continue
        if all(r[s] == "" for s in stages):  # a detector that cannot say
            continue
        if realistic:
            step, unit, frames, detected = r["size_bin"], "black_square_px", r["tags"], r["detected"]
        else:
            step = r["step"] if r["condition"] == "none" else f'{r["condition"]} {r["step"]}'
            unit, frames, detected = r["step_unit"], r["frames"], r["detected"]
        out.append({"step": step, "step_unit": unit, "detector": r["detector"], "frames": int(frames),
                    "detected": int(detected), "missed": int(frames) - int(detected),
                    **{s: int(r[s]) for s in stages}})
    if detectors:  # the detectors side by side within a step, in the order given
        order = {d: i for i, d in enumerate(detectors)}
        steps = list(dict.fromkeys(o["step"] for o in out))
        out.sort(key=lambda o: (steps.index(o["step"]), order[o["detector"]]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("summary")
    ap.add_argument("--detectors", default="")
    ap.add_argument("--format", choices=["csv", "markdown"], default="csv")
    ap.add_argument("--out")
    a = ap.parse_args()
    rows, stages = load(a.summary)
    detectors = [d for d in a.detectors.split(",") if d]
    known = {r["detector"] for r in rows}
    for d in detectors:
        if d not in known:
            fail(f"{a.summary}: no detector '{d}' (it has {', '.join(sorted(known))})")
    table = breakdown(rows, stages, detectors)
    if not table:
        fail(f"{a.summary}: no detector here can explain its misses")
    cols = ["step", "step_unit", "detector", "frames", "detected", "missed"] + stages
    if a.format == "csv":
        text = ",".join(cols + ["source"]) + "\n"
        for o in table:
            text += ",".join(str(o[c]) for c in cols) + "," + os.path.basename(a.summary) + "\n"
    else:
        used = [s for s in stages if any(o[s] for o in table)]
        head = ["step (" + table[0]["step_unit"] + ")", "detector", "frames", "detected"] + [s[5:] for s in used]
        text = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"
        for o in table:
            text += "| " + " | ".join([o["step"], o["detector"], str(o["frames"]), str(o["detected"])] +
                                      [str(o[s]) for s in used]) + " |\n"
    if a.out:
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(a.out)), prefix=".loss_breakdown.")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, a.out)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()

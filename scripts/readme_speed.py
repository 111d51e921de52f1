"""README tables of detector speed (issue 17 section 5), for update_readme.py: per image set the
per-image time ratios against the peer (`tagbench speed`, results/speed.csv) and our per-stage times
on the synthetic scenes (Google Benchmark, results/speed_stages.csv)."""
import os

from readme_common import rows, table

SET_NAMES = {"corpus": "natural photos (corpus)", "raytrace": "ray-traced frames", "realistic": "realistic set",
             "scenes": "synthetic scenes"}


def speed(d):
    body = []
    for r in rows(os.path.join(d, "speed.csv")):
        ratio = "-"
        if r["ratio_peer"]:
            ratio = (f'{float(r["ratio_geomean"]):.2f} ({float(r["ratio_ci_lo"]):.2f}-{float(r["ratio_ci_hi"]):.2f})'
                     f' vs {r["ratio_peer"]}, faster on {100 * float(r["share_faster"]):.0f} %')
        body.append([SET_NAMES.get(r["set"], r["set"]), r["detector"], r["images"], f'{float(r["megapixels"]):.0f}',
                     f'{float(r["median_ms"]):.1f}', f'{float(r["mpx_per_s"]):.1f}', ratio])
    return table(["Image set", "Detector", "Images", "Mpx", "Median ms", "Mpx/s", "Time / peer's, per image: "
                  "geometric mean (95 %)"], body)


def speed_stages(d):
    body = []
    for r in rows(os.path.join(d, "speed_stages.csv")):
        ratio = f'{float(r["ratio_to_libapriltag"]):.2f}' if r["ratio_to_libapriltag"] else "-"
        body.append([r["detector"], r["mode"], f'{r["width"]}x{r["height"]}', f'{float(r["ms_per_frame"]):.2f}',
                     r["detections"], ratio, r.get("candidate_quads", "") or "-"])
    return table(["Detector", "Mode", "Image", "ms/frame (1 thread)", "Tags found (of 6)",
                  "Ours / libapriltag", "Candidate quads"], body)


def _loss_table(path, detectors):
    import loss_breakdown
    rows_, stages = loss_breakdown.load(path)
    known = {r["detector"] for r in rows_}
    table_ = loss_breakdown.breakdown(rows_, stages, [d for d in detectors if d in known])
    used = [s for s in stages if any(o[s] for o in table_)]
    body = [[o["step"], o["detector"], o["frames"], o["detected"]] + [o[s] for s in used] for o in table_
            if o["missed"] or o["step"] in ("all",)]
    unit = table_[0]["step_unit"] if table_ else ""
    return table([f"step ({unit})", "detector", "frames", "detected"] + [s[5:] for s in used], body)


def loss_distance(d):
    """Where the distance sweep's missed tags were lost, paper profile beside the default (steps with a miss)."""
    return _loss_table(os.path.join(d, "fig10_distance_summary.csv"), ["tagbench-paper", "tagbench"])


def loss_realistic(d):
    """The same on the realistic set, per size bin."""
    return _loss_table(os.path.join(d, "realistic_summary.csv"), ["tagbench-paper", "tagbench", "tagbench-thorough"])

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

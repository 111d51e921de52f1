#!/usr/bin/python3
"""Rewrites the README's result tables from the CSVs in results/, between the markers
<!-- BEGIN:name --> and <!-- END:name -->, so no number in the README is typed by hand.
Usage: update_readme.py [README] [RESULTS_DIR]"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from readme_common import rows, table  # noqa: E402
from readme_raytrace import (RT_NAMES, _detectors, _median, raytrace_conditions, raytrace_external_claims,  # noqa: E402,F401
                             raytrace_sixdof, raytrace_summary)
from readme_speed import loss_distance, loss_realistic, speed, speed_stages  # noqa: E402
from readme_targets import issue17_targets  # noqa: E402




def code_table(d):
    body = []
    for r in rows(os.path.join(d, "code_table.csv")):
        ok = r["status"] == "ok"
        body.append([r["scheme"], f'`{r["family"]}`', r["bits"] or "36",
                     r["codes"] if ok else "(generation in progress)", r["paper_codes"] or "-",
                     r["min_hamming_with_rotations"] if ok else "-", r["paper_min_hamming"] or "-",
                     r["min_hamming_without_rotations"] if ok else "-", r["min_complexity"] if ok else "-"])
    return table(["Scheme", "Family", "Bits", "Codes (ours)", "Codes (paper)", "Min. Hamming, rotations (ours)",
                  "Min. Hamming (paper)", "Min. Hamming, no rotations", "Min. complexity"], body)


def fp_theory(d):
    body = []
    for r in rows(os.path.join(d, "fp_theory.csv")):
        ours4 = f'{float(r["fp_percent_4_rotations"]):.6f}' if r["fp_percent_4_rotations"] else "N/A"
        ours1 = f'{float(r["fp_percent_1_rotation"]):.6f}' if r["fp_percent_1_rotation"] else "N/A"
        body.append([r["family"], r["codes"], r["bits_corrected"], ours4, ours1, r["paper_fp_percent"],
                     r["paper_implied_words"] or "-"])
    return table(["Family", "Codes", "Bits corrected", "FP % (ours, 4 rotations)", "FP % (ours, 1 rotation)",
                  "FP % (paper)", "Accepted words the paper's % implies"], body)


def generator_speed(d):
    body = []
    for r in rows(os.path.join(d, "generator_speed.csv")):
        body.append([r["family"], r["source"], r["threads"], r["candidates"], r["codes"],
                     f'{float(r["wall_seconds"]):.3g}', f'{float(r["candidates_per_second"]):.3g}',
                     f'{float(r["candidates_per_second_per_thread"]):.3g}', r["matches_shipped"]])
    return table(["Family", "Source", "Threads", "Candidates", "Codes", "Wall s", "Candidates/s", "Per thread",
                  "Equals shipped"], body)


def decode_speed(d):
    body = []
    for r in rows(os.path.join(d, "decode_speed.csv")):
        items = r.get("items_per_second") or ""
        body.append([f'`{r["name"]}`', f'{float(r["real_time"]):.1f} {r["time_unit"]}',
                     f'{float(items):.3g}' if items else "-", r.get("label", "")])
    return table(["Benchmark", "Time per call", "Items/s", "Scan"], body)


def pending(_d):
    fam_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "detector", "codes", "families")
    ck_dir = os.path.join(fam_dir, "checkpoints")
    lines = []
    for name in sorted(os.listdir(ck_dir)) if os.path.isdir(ck_dir) else []:
        if not name.endswith(".ckpt") or os.path.exists(os.path.join(fam_dir, name[:-5] + ".fam")):
            continue
        keys = {}
        for line in open(os.path.join(ck_dir, name)):
            if ":" in line and not line.startswith("#"):
                k, v = line.split(":", 1)
                keys[k.strip()] = v.strip()
        done = int(keys["next_index"]) / 2 ** int(keys["bits"])
        fam = name[:-5][3:] if name.startswith("tag") else name[:-5]
        lines.append(f'- `{fam}`: {100 * done:.1f} % of the candidates examined, {keys["count"]} codes '
                     f'accepted so far, {float(keys["elapsed_seconds"]) / 3600:.2f} h of generation.')
    return "\n".join(lines) if lines else "All shipped families are complete."


def _g(x):
    return f"{float(x):.2g}" if float(x) else "0"


def _rate_ci(r):
    return f'{_g(r["rate"])} ({r["accepted"]}; {_g(r["ci95_lo"])}-{_g(r["ci95_hi"])})'


def fig6_table(d):
    """Complexity -> rate at each k (all images), with the random-payload rate."""
    by = {}
    ks = []
    for r in rows(os.path.join(d, "fig6_complexity.csv")):
        if r["subset"] != "all":
            continue
        by.setdefault((int(r["min_complexity"]), r["codes"]), {})[int(r["bits_corrected"])] = r
        ks = sorted(set(ks) | {int(r["bits_corrected"])})
    body = []
    for (c, codes), per_k in sorted(by.items()):
        body.append([c, codes] + [f'{_rate_ci(per_k[k])}; theory {_g(per_k[k]["theory_rate"])}' for k in ks])
    quads = next(iter(next(iter(by.values())).values()))["quads"]
    return (f"Rate per candidate quad ({quads} 5x5 candidate quads), in brackets the accepted count and the 95 % "
            "Wilson interval; theory = 4 N V(25, k) / 2^25.\n\n" +
            table(["Min. complexity", "Codes"] + [f"k = {k}" for k in ks], body))


def fig7_table(d):
    by = {}
    ks = []
    for r in rows(os.path.join(d, "fig7_codes.csv")):
        if r["subset"] != "all":
            continue
        by.setdefault((r["scheme"], r["codes"]), {})[int(r["bits_corrected"])] = r
        ks = sorted(set(ks) | {int(r["bits_corrected"])})
    body = []
    for (scheme, codes), per_k in by.items():
        body.append([scheme, codes] + [f'{_rate_ci(per_k[k])}; theory {_g(per_k[k]["theory_rate"])}'
                                       + ("" if per_k[k]["theory_exact"] == "1" else "*") for k in ks])
    quads = next(iter(next(iter(by.values())).values()))["quads"]
    return (f"Rate per candidate quad ({quads} 6x6 candidate quads), in brackets the accepted count and the 95 % "
            "Wilson interval; theory = 4 N V(36, k) / 2^36, exact while 2k < h, an upper bound where marked *.\n\n" +
            table(["Scheme", "Codes"] + [f"k = {k}" for k in ks], body))


def fp_detectors_table(d):
    body = []
    rs = rows(os.path.join(d, "fp_detectors.csv"))
    for r in rs:
        if r["subset"] != "all":
            continue
        sub = {x["subset"]: x for x in rs if x["detector"] == r["detector"] and x["family"] == r["family"]}
        cell = lambda x: (f'{_g(x["per_megapixel"])} ({x["detections"]}; {_g(x["per_megapixel_ci95_lo"])}-'
                          f'{_g(x["per_megapixel_ci95_hi"])})') if x else "-"
        body.append([r["detector"], r["family"], cell(sub.get("still")), cell(sub.get("video-frame")),
                     f'{_g(r["per_image"])} ({_g(r["per_image_ci95_lo"])}-{_g(r["per_image_ci95_hi"])})',
                     f'{100 * float(r["image_share"]):.2g} % ({r["images_with_detections"]} of {r["images"]})',
                     f'{float(r["ms_per_image"]):.1f}', f'{float(r["megapixels_per_second"]):.3g}'])
    return table(["Detector", "Family", "Stills: per Mpx (count; 95 %)", "Video frames: per Mpx (count; 95 %)",
                  "All: per image (95 %)", "Images with one", "ms per image", "Mpx/s (1 thread)"], body)


def fp_detectors_groups(d):
    """Per group: false detections per megapixel of each detector (36h11 and 16h5 columns)."""
    rs = rows(os.path.join(d, "fp_detectors.csv"))
    cols = []
    for r in rs:
        if r["subset"] == "all" and (r["detector"], r["family"]) not in cols:
            cols.append((r["detector"], r["family"]))
    groups = []
    for r in rs:
        if r["subset"].startswith("group:") and r["subset"] not in groups:
            groups.append(r["subset"])
    idx = {(r["detector"], r["family"], r["subset"]): r for r in rs}
    body = []
    for g in groups:
        first = idx[(cols[0][0], cols[0][1], g)]
        body.append([g[6:], first["images"], f'{float(first["megapixels"]):.0f}'] +
                    [idx[(dt, fm, g)]["detections"] if (dt, fm, g) in idx else "-" for dt, fm in cols])
    return table(["Group", "Images", "Mpx"] + [f"{dt} {fm}" for dt, fm in cols], body)


def corpus_groups(d):
    body = []
    for r in rows(os.path.join(d, "corpus_groups.csv")):
        body.append([r["group"], r["kind"], r["images"], f'{float(r["megapixels"]):.1f}', r["candidate_quads"],
                     r["packages"], r["licences"]])
    return table(["Group", "Kind", "Images", "Mpx", "Candidate quads", "Debian package", "Licence"], body)


def corpus_extraction(d):
    body = []
    for r in rows(os.path.join(d, "corpus_extraction.csv")):
        body.append([r["stage"], r["images"], r["megapixels"], r["seconds"], r["images_per_second"],
                     r["megapixels_per_second"], r["jobs"], r["measured"]])
    return table(["Stage", "Images", "Mpx", "Seconds", "Images/s", "Mpx/s", "Threads", "Measured"], body)


def fuzz(d):
    body = []
    for r in rows(os.path.join(d, "fuzz_summary.csv")):
        body.append([f'`{r["target"]}`', r["runs"], f'{int(r["seconds"]) / 60:.1f}', r["executions"],
                     r["max_coverage"], r["crashes"]])
    return table(["Target", "Runs", "Minutes", "Executions", "Coverage (max)", "Runs with a finding (fixed)"], body)


def memory(d):
    body = []
    for r in rows(os.path.join(d, "memory.csv")):
        body.append([f'{r["width"]} x {r["height"]}', "half" if r["half_resolution"] == "1" else "full",
                     r["peak_rss_mb"], r["bytes_per_pixel"], r["workspace_mb"], r["warm_frame_peak_mb"],
                     r["detect_ms"]])
    return table(["Image", "Resolution", "Peak MB", "Bytes/pixel", "Workspace MB", "Second frame adds, MB",
                  "Detect ms"], body)


def margin_table(d):
    """Per family, a minimum decision margin every 0.1: false detections on the corpus against the
    ray-traced detection rates (results/margin_tradeoff.csv)."""
    rs = rows(os.path.join(d, "margin_tradeoff.csv"))
    parts = [k[:-len("_frames")] for k in rs[0] if k.endswith("_frames")] if rs else []
    body = []
    for r in rs:
        t = float(r["threshold"])
        if abs(t * 10 - round(t * 10)) > 1e-9:
            continue
        cells = [r["family"], f"{t:g}",
                 f'{_g(r["fp_per_image"])} ({r["false_detections"]}; {_g(r["fp_per_image_ci95_lo"])}-'
                 f'{_g(r["fp_per_image_ci95_hi"])})',
                 f'{100 * float(r["image_share"]):.2g} % ({r["images_with_false"]})']
        for p in parts:
            cells.append(f'{100 * float(r[p + "_rate"]):.1f} % ({r[p + "_detected"]} of {r[p + "_frames"]})')
        if "distance_range_m" in r:
            cells.append(f'{_g(r["distance_range_m"])} m')
        body.append(cells)
    head = ["Family", "Min margin", "False per image (count; 95 %)", "Images with one"]
    head += [f"Ray-traced {p}: detected" for p in parts]
    if rs and "distance_range_m" in rs[0]:
        head.append("Range (>= 90 % at every step)")
    return table(head, body)


def margin_findings(d):
    """Per family: the largest threshold that costs at most 1 % of any part's real detections (against
    margin 0), and what it saves; from results/margin_tradeoff.csv."""
    rs = rows(os.path.join(d, "margin_tradeoff.csv"))
    parts = [k[:-len("_frames")] for k in rs[0] if k.endswith("_frames")] if rs else []
    out = []
    for fam in dict.fromkeys(r["family"] for r in rs):
        fr = [r for r in rs if r["family"] == fam]
        base = fr[0]
        if float(base["threshold"]) != 0:
            continue
        free = base
        for r in fr:
            lost = [(int(base[p + "_detected"]) - int(r[p + "_detected"])) / max(1, int(base[p + "_frames"]))
                    for p in parts]
            if max(lost) <= 0.01:
                free = r
            else:
                break
        f0, f1 = int(base["false_detections"]), int(free["false_detections"])
        fp_text = (f'It removes {100 * (f0 - f1) / f0:.0f} % of the false detections ({_g(base["fp_per_image"])} -> '
                   f'{_g(free["fp_per_image"])} per image, images with one {100 * float(base["image_share"]):.0f} -> '
                   f'{100 * float(free["image_share"]):.0f} %)' if f0 else
                   "There are no false detections to remove at margin 0 on this corpus")
        rates = ", ".join(f'{p} {100 * float(base[p + "_rate"]):.1f} -> {100 * float(free[p + "_rate"]):.1f} %'
                          for p in parts)
        rng = (f'; range {_g(base["distance_range_m"])} -> {_g(free["distance_range_m"])} m'
               if "distance_range_m" in base else "")
        out.append(f'- **{fam}**: the largest threshold that loses at most 1 % of the real detections of every '
                   f'part is {float(free["threshold"]):g}. {fp_text}; real tags detected: {rates}{rng}.')
    return "\n".join(out)


def _realistic_rates(d, ceiling=False):
    """Per size bin (rows) and detector (columns) of d/realistic_summary.csv: detection rate % [Wilson 95 %],
    wrong ids and false detections where there are any (a bin with no tag, "<12" or ">40", holds false
    detections only: its rate is "-"); with `ceiling`, a column of the share the payload
    readers decode through the true corners (d/realistic_ceiling_summary.csv, `realistic --ceiling`)."""
    summary = rows(os.path.join(d, "realistic_summary.csv"))
    reads = {r["size_bin"]: r for r in rows(os.path.join(d, "realistic_ceiling_summary.csv"))
             if r["contrast_band"] == "all"} if ceiling else {}
    bins, dets = [], _detectors(summary)
    for r in summary:
        if r["size_bin"] not in bins:
            bins.append(r["size_bin"])
    body = []
    for b in bins:
        sel = {r["detector"]: r for r in summary if r["size_bin"] == b}
        tags = int(next(iter(sel.values()))["tags"])
        row = [f"{b} px" if b != "all" else "all", str(tags)]
        if ceiling:
            row.append(f'{100 * int(reads[b]["ceiling_either"]) / tags:.0f}' if b in reads else "-")
        for det in dets:
            if det not in sel:  # a detector without a row in this bin
                row.append("-")
                continue
            r = sel[det]
            wrong = r.get("wrong_id_tags", "0") or "0"
            rate = (f'{100 * float(r["detection_rate"]):.0f} [{100 * float(r["rate_lo95"]):.0f}-'
                    f'{100 * float(r["rate_hi95"]):.0f}]' if tags else "-")  # a bin of false detections only
            row.append(rate + (f", {wrong} wrong id" if wrong != "0" else "")
                       + (f', {r["false_detections"]} false' if r["false_detections"] != "0" else ""))
        body.append(row)
    head = ["Black square", "Tags"] + (["Readable from the true corners, %"] if ceiling else [])
    return table(head + [RT_NAMES.get(x, x) for x in dets], body)


def realistic_table(d):
    """The realistic set of make bench (seed 1): rates per size bin and detector."""
    return _realistic_rates(d)


def realistic_seed2_table(d):
    """The held-out realistic set (seed 2, results/realistic_seed2/): rates and the readers' ceiling."""
    return _realistic_rates(os.path.join(d, "realistic_seed2"), ceiling=True)


def realistic_family_table(d, family):
    """The realistic set (seed 1) in another family (results/realistic_<family>/): rates, wrong ids, false."""
    return _realistic_rates(os.path.join(d, "realistic_" + family))


def realistic_corners(d):
    """Corner accuracy on the realistic sets (36h11 seeds 1 and 2, 16h5, 25h9, seed 1 from a linear camera;
    d/realistic*/realistic.csv):
    per set, the median and 90th percentile of the corner RMS error (px) of our default profile and of
    each peer, over the tags both found with the right id: a like-for-like comparison, as each finds
    different tags."""
    sets = [("36h11, seed 1", "realistic.csv"), ("36h11, seed 2", os.path.join("realistic_seed2", "realistic.csv")),
            ("16h5", os.path.join("realistic_16h5", "realistic.csv")), ("25h9", os.path.join("realistic_25h9", "realistic.csv")),
            ("36h11, seed 1, linear camera", os.path.join("realistic_linear", "realistic.csv"))]
    peers = ["libapriltag-d1", "libapriltag-d2", "aruco"]
    body = []
    for label, f in sets:
        err = {}
        for r in rows(os.path.join(d, f)):
            if r["detected"] == "1" and r["wrong_id"] == "0" and r["corner_rms_px"]:
                err.setdefault(r["detector"], {})[(r["frame"], r["tag"])] = float(r["corner_rms_px"])
        ours = err.get("tagbench", {})
        row = [label]
        for peer in peers:
            both = sorted(set(ours) & set(err.get(peer, {})))
            if not both:
                row.append("-")
                continue
            a = sorted(ours[k] for k in both)
            b = sorted(err[peer][k] for k in both)
            p90 = lambda v: v[min(len(v) - 1, int(0.9 * len(v)))]
            row.append(f"{len(both)}: {_median(a):.3f} / {p90(a):.3f} vs {_median(b):.3f} / {p90(b):.3f}")
        body.append(row)
    return table(["Set (200 frames)"] + [f"tags both found: ours vs {RT_NAMES.get(p, p)}, median / p90 px" for p in peers],
                 body)


BLOCKS = {"pending": pending,
          "realistic_corners": realistic_corners,
          "realistic_seed2_table": realistic_seed2_table,
          "realistic_16h5_table": lambda d: realistic_family_table(d, "16h5"),
          "realistic_25h9_table": lambda d: realistic_family_table(d, "25h9"),
          "realistic_linear_table": lambda d: _realistic_rates(os.path.join(d, "realistic_linear")),
          "speed": speed, "speed_stages": speed_stages, "loss_distance": loss_distance,
          "loss_realistic": loss_realistic, "issue17_targets": issue17_targets, "code_table": code_table, "fp_theory": fp_theory, "generator_speed": generator_speed,
          "decode_speed": decode_speed, "raytrace_summary": raytrace_summary,
          "raytrace_external_claims": raytrace_external_claims,
          "raytrace_conditions": raytrace_conditions, "raytrace_sixdof": raytrace_sixdof, "fig6_table": fig6_table, "fig7_table": fig7_table,
          "fp_detectors_table": fp_detectors_table, "fp_detectors_groups": fp_detectors_groups,
          "corpus_groups": corpus_groups, "corpus_extraction": corpus_extraction, "fuzz": fuzz, "memory": memory,
          "margin_table": margin_table, "margin_findings": margin_findings, "realistic_table": realistic_table}


def main():
    readme = sys.argv[1] if len(sys.argv) > 1 else "README.md"
    results = sys.argv[2] if len(sys.argv) > 2 else "results"
    text = open(readme).read()
    for name, fn in BLOCKS.items():
        pat = re.compile(rf"(<!-- BEGIN:{name} -->\n).*?(<!-- END:{name} -->)", re.S)
        if not pat.search(text):
            sys.exit(f"update_readme.py: {readme} has no block {name}")
        try:
            body = fn(results)
        except FileNotFoundError as e:
            sys.exit(f"update_readme.py: {e.filename}: missing (run make bench)")
        text = pat.sub(lambda m: m.group(1) + body + "\n" + m.group(2), text)
    tmp = readme + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, readme)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Where the planar pose ambiguity is chosen wrong, and whether the other solution is right (an oracle).

Reads a dataset exported by `tagbench dataset export` (truth.json) and `tagbench detect ... --format json`
run on its frames with the dataset's camera (so that each detection has "pose" and, when the ambiguity
has a second solution, "pose_alternative"). For every frame whose tag was detected with the right id
(the detection whose corners are nearest the truth), the orientation error of the reported pose and of
the alternative (the angle of R_est^T R_true, degrees). Prints: how many detections are more than
--bad degrees off, how they spread over black-square size, phi, noise and defocus, and the share of
them whose alternative is within --good degrees (choosing the other solution would fix it); also how
many right poses the alternative would break. With --csv FILE, one row per detected frame.

Usage: pose_ambiguity.py DATASET_DIR DETECT_JSON [--bad 10] [--good 5] [--csv FILE]
"""
import argparse
import csv
import json
import math
import os
import sys


def angle_deg(Ra, Rb):
    # trace(Ra^T Rb) = sum_ij Ra_ij Rb_ij
    tr = sum(Ra[i][j] * Rb[i][j] for i in range(3) for j in range(3))
    return math.degrees(math.acos(max(-1.0, min(1.0, (tr - 1) / 2))))


def corner_rms(a, b):
    return math.sqrt(sum((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 for p, q in zip(a, b)) / 4)


def bins_of(rows, key, edges):
    out = []
    for lo, hi in zip(edges, edges[1:]):
        sel = [r for r in rows if lo <= r[key] < hi]
        out.append((lo, hi, sel))
    return out


def load(path, key):
    """A JSON object holding `key`, or a one-line refusal naming the file and the problem."""
    try:
        with open(path) as fh:
            data = json.load(fh)
    except OSError as e:
        sys.exit(f"pose_ambiguity.py: {path}: {e.strerror}")
    except ValueError as e:
        sys.exit(f"pose_ambiguity.py: {path}: not JSON ({e})")
    if not isinstance(data, dict) or key not in data:
        sys.exit(f'pose_ambiguity.py: {path}: no "{key}" list (a dataset\'s truth.json / detect --format json?)')
    return data


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dataset")
    ap.add_argument("detections")
    ap.add_argument("--bad", type=float, default=10)
    ap.add_argument("--good", type=float, default=5)
    ap.add_argument("--csv")
    a = ap.parse_args()
    truth = load(os.path.join(a.dataset, "truth.json"), "frames")
    det = load(a.detections, "images")
    by_file = {os.path.basename(im["input"]): im for im in det["images"]}
    rows = []
    for f in truth["frames"]:
        im = by_file.get(f["file"])
        if im is None:
            sys.exit(f"pose_ambiguity.py: {a.detections}: no image {f['file']}")
        best = None
        for d in im["detections"]:
            if d["id"] != f["id"] or "pose" not in d:
                continue
            e = corner_rms(d["corners"], f["corners"])
            if best is None or e < best[0]:
                best = (e, d)
        if best is None:
            continue
        d = best[1]
        err = angle_deg(d["pose"]["R"], f["R"])
        alt = d.get("pose_alternative")
        ce = f.get("camera_effects", {})
        rows.append(dict(file=f["file"], black_square_px=f["black_square_px"], phi_deg=f["view"]["phi_deg"],
                         distance_m=f["view"]["distance_m"], noise_sigma=ce.get("noise_sigma", 0),
                         defocus_sigma_px=ce.get("defocus_sigma_px", 0), corner_rms_px=best[0], err_deg=err,
                         alt_err_deg=angle_deg(alt["R"], f["R"]) if alt else float("nan"),
                         rms_px=d["pose"]["reprojection_rms_px"],
                         alt_rms_px=alt["reprojection_rms_px"] if alt else float("nan"),
                         ambiguous=d.get("pose_ambiguous", False),
                         margin=d.get("decision_margin", float("nan"))))
    n = len(rows)
    bad = [r for r in rows if r["err_deg"] > a.bad]
    fixable = [r for r in bad if r["alt_err_deg"] <= a.good]
    broken = [r for r in rows if r["err_deg"] <= a.good and r["alt_err_deg"] > a.bad]
    errs = sorted(r["err_deg"] for r in rows)

    def q(p):
        if not errs:
            return float("nan")
        k = (len(errs) - 1) * p
        i = int(k)
        return errs[i] + (errs[min(i + 1, len(errs) - 1)] - errs[i]) * (k - i)

    print(f"detected {n}; orientation error median {q(0.5):.3f} p90 {q(0.9):.3f} deg; > {a.bad:g} deg: {len(bad)}")
    print(f"  of those, the alternative within {a.good:g} deg: {len(fixable)} ({100 * len(fixable) / max(1, len(bad)):.0f} %);"
          f" no alternative: {sum(1 for r in bad if math.isnan(r['alt_err_deg']))}")
    print(f"  right poses (<= {a.good:g} deg) whose alternative is > {a.bad:g} deg off: {len(broken)}")
    amb = [r for r in rows if r["ambiguous"] is True]
    if amb:
        print(f"  flagged ambiguous: {len(amb)}, of them > {a.bad:g} deg off: {sum(1 for r in amb if r['err_deg'] > a.bad)};"
              f" bad not flagged: {sum(1 for r in bad if r['ambiguous'] is not True)}")
    for key, edges in [("black_square_px", [0, 15, 20, 30, 50, 1000]), ("phi_deg", [0, 10, 20, 30, 40, 55, 70, 91]),
                       ("noise_sigma", [0, 1, 2, 3, 4.01]), ("defocus_sigma_px", [0, 0.5, 1.0, 1.51])]:
        print(f"by {key}: bin: detected, > {a.bad:g} deg, of them fixable by the alternative")
        for lo, hi, sel in bins_of(rows, key, edges):
            b = [r for r in sel if r["err_deg"] > a.bad]
            fx = [r for r in b if r["alt_err_deg"] <= a.good]
            print(f"  [{lo:g}, {hi:g}): {len(sel)}, {len(b)}, {len(fx)}")
    if a.csv:
        tmp = a.csv + ".tmp"
        with open(tmp, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()) if rows else ["file"])
            w.writeheader()
            w.writerows(rows)
        os.replace(tmp, a.csv)


if __name__ == "__main__":
    main()

"""The default profile's targets (issue 17 section 5), each checked against the CSVs of `make bench`,
for update_readme.py: one row per target with what was measured and whether it is met."""
import os

from readme_common import rows, table

OURS, OURS_HALF, PAPER, THOROUGH = "tagbench", "tagbench-half", "tagbench-paper", "tagbench-thorough"
D1, D2 = "libapriltag-d1", "libapriltag-d2"
SMALL_FAMILIES = ("16h5", "25h9")  # distance sweeps beside 36h11's (issue 17 section 5)


def _f(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def _by(summary, detector):
    return [r for r in summary if r["detector"] == detector]


def _yes(ok):
    return "**met**" if ok else "not met"


def _ceiling(d, size_bin):
    """The payload readers' ceiling in one size bin (`realistic --ceiling`: each tag read through its true
    corners), as text for the 95 % row, or "" when the run had no --ceiling."""
    path = os.path.join(d, "realistic_ceiling_summary.csv")
    if not os.path.exists(path):
        return ""
    row = next((r for r in rows(path) if r["size_bin"] == size_bin and r["contrast_band"] == "all"), None)
    if row is None:
        return ""
    either, tags = int(row["ceiling_either"]), int(row["tags"])
    return f"; read from the true corners at most {either}/{tags} = {100 * either / tags:.1f} %"


def _realistic(d):
    s = rows(os.path.join(d, "realistic_summary.csv"))
    ours = {r["size_bin"]: r for r in _by(s, OURS)}
    d1 = {r["size_bin"]: r for r in _by(s, D1)}
    bins = [b for b in ours if b != "all"]
    short = [b for b in bins if _f(ours[b]["detection_rate"]) < _f(d1[b]["detection_rate"])]
    wrong = sum(int(ours[b]["wrong_id_tags"] or 0) for b in bins)
    detail = ", ".join(f'{b}: {100 * _f(ours[b]["detection_rate"]):.0f} vs {100 * _f(d1[b]["detection_rate"]):.0f} %'
                       for b in bins)
    out = [["Realistic set: every size bin >= libapriltag d1, no wrong id", detail + f"; wrong ids {wrong}",
            _yes(not short and wrong == 0) + (f" (short at {', '.join(short)})" if short else "")]]
    b20 = next((b for b in bins if b.startswith("20-")), None)
    if b20:
        r = _f(ours[b20]["detection_rate"])
        # The thorough profile (the default with full-resolution line quads and the coarse pass) is no target's
        # subject: its rate is given beside the default's, which the target is about, as a count and to
        # a tenth of a percent (94.7 % is not 95 %).
        thorough = {x["size_bin"]: x for x in _by(s, THOROUGH)}.get(b20)
        beside = (f'; thorough profile {thorough["detected"]} of {thorough["tags"]}, '
                  f'{100 * _f(thorough["detection_rate"]):.1f} %' if thorough else "")
        out.append([f"Realistic set: >= 95 % at 20 px ({b20} px bin)", f"{100 * r:.0f} % (libapriltag d1 "
                    f'{100 * _f(d1[b20]["detection_rate"]):.0f} %{beside})' + _ceiling(d, b20), _yes(r >= 0.95)])
    return out


def _reach_rows(s, family):
    """The range targets of one family's distance sweep summary: >= 99 % down to <= 10 px, >= d1 at every step."""
    ours, d1 = _by(s, OURS), {r["step"]: r for r in _by(s, D1)}
    reach = None
    for r in ours:
        if _f(r["detection_rate"]) < 0.99:
            break
        reach = r
    below = [r["step"] for r in ours if r["step"] in d1 and _f(r["detection_rate"]) < _f(d1[r["step"]]["detection_rate"])]
    px = _f(reach["black_square_px_median"]) if reach else None
    return [[f"Distance sweep ({family}): >= 99 % down to a black square of 10 px or less",
             f'>= 99 % to {reach["step"]} m ({px:.1f} px)' if reach else "below 99 % at the first step",
             _yes(px is not None and px <= 10)],
            [f"Distance sweep ({family}): >= libapriltag d1 at every step",
             "below at " + (", ".join(below) + " m" if below else "no step"), _yes(not below)]]


def _distance(d):
    s = rows(os.path.join(d, "fig10_distance_summary.csv"))
    ours = _by(s, OURS)
    out = _reach_rows(s, "36h11")
    # The small families' sweeps (make bench: fig10_distance_16h5*.csv, fig10_distance_25h9*.csv).
    for family in SMALL_FAMILIES:
        path = os.path.join(d, f"fig10_distance_{family}_summary.csv")
        if os.path.exists(path):
            out += _reach_rows(rows(path), family)
        else:
            out.append([f"Distance sweep ({family}): >= 99 % to 10 px and >= libapriltag d1 at every step",
                        f"not measured ({os.path.basename(path)} missing)", "not met"])
    paper = {r["step"]: r for r in _by(s, PAPER)}
    worse = [r["step"] for r in ours if _f(r["step"]) <= 10 and r["step"] in paper and
             _f(r["corner_rms_px_median"]) is not None and
             _f(r["corner_rms_px_median"]) > _f(paper[r["step"]]["corner_rms_px_median"])]
    span = [_f(r["corner_rms_px_median"]) for r in ours if _f(r["step"]) <= 10]
    pspan = [_f(paper[r["step"]]["corner_rms_px_median"]) for r in ours if _f(r["step"]) <= 10 and r["step"] in paper]
    out.append(["Median corner error on the distance sweep to 10 m no worse than the paper profile",
                (f"{min(span):.3f}-{max(span):.3f} px" if span else "-") +
                (f" (paper {min(pspan):.3f}-{max(pspan):.3f} px)" if pspan else "") + "; worse at "
                + (", ".join(worse) + " m" if worse else "no step"), _yes(not worse)])
    return out


def _angle(d):
    s = rows(os.path.join(d, "fig9_angle_summary.csv"))
    ours, d1 = _by(s, OURS), {r["step"]: r for r in _by(s, D1)}
    below = [r["step"] for r in ours if r["step"] in d1 and _f(r["detection_rate"]) < _f(d1[r["step"]]["detection_rate"])]
    # The default profile at half resolution refines its corners on the full image, so its median can
    # equal ours to a few thousandths of a degree: said apart, as it is the same profile, not a peer.
    not_best, own_half = [], []
    for r in ours:
        if _f(r["step"]) > 70:
            continue
        mine = _f(r["orientation_error_deg_median"])
        others = {o["detector"]: _f(o["orientation_error_deg_median"]) for o in s
                  if o["step"] == r["step"] and o["detector"] != OURS}
        lower = {k: v for k, v in others.items() if v is not None and mine is not None and v < mine}
        if mine is None or any(k != OURS + "-half" for k in lower):
            not_best.append(r["step"])
        elif lower:
            own_half.append((r["step"], mine - lower[OURS + "-half"]))
    text = "not lowest at " + (", ".join(not_best) + " deg" if not_best else "no phi")
    if own_half:
        text += (f"; {OURS}-half (the same profile, corners refined on the full image) lower by at most "
                 f"{max(d for _, d in own_half):.4f} deg at " + ", ".join(p for p, _ in own_half) + " deg")
    return [["Angle sweep: >= libapriltag d1 at every phi", "below at " + (", ".join(below) + " deg" if below else
                                                                       "no phi"), _yes(not below)],
            ["Angle sweep: lowest median orientation error of all detectors at every phi to 70 deg", text,
             _yes(not not_best)]]


def _conditions(d):
    s = rows(os.path.join(d, "conditions_summary.csv"))
    ours = _by(s, OURS)
    blur4 = next((r for r in ours if r["condition"] == "blur" and _f(r["step"]) == 4), None)
    # "100 % as today": today = the detector before issue 17, which the paper profile reproduces byte for byte,
    # so its rows in the same run are the baseline. Where it was below 100 % (bent 30, 40 deg) the issue asks
    # for nothing; we hold ours to libapriltag d1's rate there, a row of its own.
    paper = {(r["condition"], r["step"]): _f(r["detection_rate"]) for r in _by(s, PAPER)}
    d1 = {(r["condition"], r["step"]): _f(r["detection_rate"]) for r in _by(s, D1)}
    other = [r for r in ours if r["condition"] not in ("occlusion", "blur") or
             (r["condition"] == "blur" and _f(r["step"]) != 4)]
    was_full = [r for r in other if paper.get((r["condition"], r["step"])) == 1]
    below = [f'{r["condition"]} {r["step"]}' for r in was_full if _f(r["detection_rate"]) < 1]
    hard = [r for r in other if (r["condition"], r["step"]) in paper and paper[(r["condition"], r["step"])] < 1]
    hard_text = ", ".join(f'{r["condition"]} {r["step"]}: {100 * _f(r["detection_rate"]):.0f} % (before '
                          f'{100 * paper[(r["condition"], r["step"])]:.0f} %, libapriltag d1 '
                          f'{100 * d1.get((r["condition"], r["step"]), 0):.0f} %)' for r in hard)
    hard_ok = all(_f(r["detection_rate"]) >= d1.get((r["condition"], r["step"]), 0) for r in hard)
    out = [["Conditions: blur sigma 4 px >= 98 %", f'{100 * _f(blur4["detection_rate"]):.0f} %' if blur4 else "-",
            _yes(blur4 is not None and _f(blur4["detection_rate"]) >= 0.98)],
           ["Conditions: every other condition and strength 100 % as before issue 17 (where the paper profile, "
            "the detector before it, had 100 %)",
            f"{len(was_full)} condition steps; below 100 % at " + (", ".join(below) if below else "none"),
            _yes(bool(was_full) and not below)]]
    if hard:
        out.append(["Conditions below 100 % before issue 17 (not a target of the issue): >= libapriltag d1",
                    hard_text, _yes(hard_ok)])
    per = rows(os.path.join(d, "conditions.csv"))
    occ = [r for r in per if r["detector"] == OURS and r["condition"] == "occlusion" and _f(r["step"]) > 0]
    rep = [r for r in occ if r["detected_right_id"] == "1"]
    good = [r for r in rep if _f(r["corner_rms_px"]) <= 1 and _f(r["orientation_error_deg"]) is not None and
            _f(r["orientation_error_deg"]) <= 2]
    wrong = sum(1 for r in occ if r["wrong_id"] == "1")
    share = len(good) / len(rep) if rep else None
    out.append(["Occlusion (20-80 % of an edge): of the frames reported, >= 90 % within 1 px RMS and 2 deg",
                f"{len(rep)} of {len(occ)} frames reported, {len(good)} of them accurate; {wrong} wrong ids"
                + ("" if rep else " (a partly hidden tag is withdrawn, never reported wrong)"),
                ("met only by withdrawing: no occluded tag is reported" if not rep and wrong == 0 else
                 _yes((share is None or share >= 0.9) and wrong == 0))])
    return out


def _speed(d):
    out = []
    for r in rows(os.path.join(d, "speed.csv")):
        if r["detector"] in (OURS, OURS_HALF) and r["ratio_peer"]:
            g = _f(r["ratio_geomean"])
            out.append([f'Speed, {r["set"]}: {r["detector"]} / {r["ratio_peer"]} <= 1.0',
                        f'{g:.2f} ({_f(r["ratio_ci_lo"]):.2f}-{_f(r["ratio_ci_hi"]):.2f}), {r["images"]} images; '
                        f'stretch 0.7 {"met" if g <= 0.7 else "not met"}',
                        _yes(g <= 1.0)])
    return out


def _false_positives(d):
    s = {(r["detector"], r["family"]): r for r in rows(os.path.join(d, "fp_detectors.csv")) if r["subset"] == "all"}
    out = []
    o, p = s.get((OURS, "16h5")), s.get((D2, "16h5"))
    if o and p:
        out.append(["16h5 false detections per corpus image <= libapriltag d2",
                    f'{_f(o["per_image"]):.3f} vs {_f(p["per_image"]):.2f}', _yes(_f(o["per_image"]) <= _f(p["per_image"]))])
    o = s.get((OURS, "36h11"))
    if o:
        out.append(["36h11 false detections: zero", o["detections"], _yes(o["detections"] == "0")])
    return out


def issue17_targets(d):
    body = _realistic(d) + _distance(d) + _angle(d) + _conditions(d) + _speed(d) + _false_positives(d)
    return table(["Target (issue 17)", "Measured (make bench)", ""], body)

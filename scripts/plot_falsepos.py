#!/usr/bin/python3
"""Plots the false-positive experiments on the natural-image corpus (paper section VI-A):
  fig6_complexity.png  from fig6_complexity.csv: 25h9 families of minimum complexity 1..10 (Fig. 6)
  fig7_codes.png       from fig7_codes.csv: ARToolKit+ simple/BCH, ARTag, 36h10, 36h15, 36h11 (Fig. 7)
  fp_detectors.png     from fp_detectors.csv: whole detectors' false detections per megapixel
  margin_tradeoff.png  from margin_tradeoff.csv and margin_tradeoff_steps.csv: a minimum decision
                       margin against false detections per image and ray-traced detection rates
Each rate is drawn with its 95 % confidence interval; a rate of 0 is drawn at the bottom of the
log axis with its interval's upper bound. Usage: plot_falsepos.py RESULTS_DIR [fig6] [fig7] [detectors] [margin]
(default: every plot whose CSV exists). PNGs are written atomically."""
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)
    plt.close(fig)


def curves(rows, subset="all"):
    """scheme -> (k list, rate, lo, hi, theory, codes, quads)"""
    out = OrderedDict()
    for r in rows:
        if r["subset"] != subset:
            continue
        c = out.setdefault(r["scheme"], ([], [], [], [], [], r["codes"], r["quads"]))
        c[0].append(int(r["bits_corrected"]))
        c[1].append(float(r["rate"]))
        c[2].append(float(r["ci95_lo"]))
        c[3].append(float(r["ci95_hi"]))
        c[4].append(float(r["theory_rate"]))
    return out


def draw_rate(ax, ks, rate, lo, hi, floor, color, label, **kw):
    """A rate curve with its interval. Zero rates (nothing accepted) cannot sit on a log axis: they
    are drawn as open down-triangles on `floor`, with a bar up to the interval's upper bound."""
    nz = [i for i, r in enumerate(rate) if r > 0]
    ax.errorbar([ks[i] for i in nz], [rate[i] for i in nz],
                yerr=[[rate[i] - lo[i] for i in nz], [hi[i] - rate[i] for i in nz]],
                capsize=2, color=color, label=label, **kw)
    z = [i for i, r in enumerate(rate) if r <= 0]
    if z:
        ax.errorbar([ks[i] for i in z], [floor] * len(z), yerr=[[0] * len(z), [hi[i] - floor for i in z]],
                    fmt="v", mfc="none", color=color, capsize=2, ms=5)


def curve_plot(results, name):
    """The curves of a scoring CSV (all images), its quad count, the log axis' floor for zero rates
    (a third of one quad) and a fresh figure."""
    cs = curves(read(os.path.join(results, name)))
    if not cs:
        sys.exit(f"plot_falsepos.py: {name} has no rows")
    quads = int(next(iter(cs.values()))[6])
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    return cs, quads, 0.3 / quads, fig, ax


def fig6(results):
    cs, quads, floor, fig, ax = curve_plot(results, "fig6_complexity.csv")
    cmap = plt.get_cmap("viridis")
    n = len(cs)
    theory_lo, theory_hi, ks_all = None, None, None
    for i, (scheme, (ks, rate, lo, hi, th, codes, _)) in enumerate(cs.items()):
        c = scheme.split(">=")[-1].strip()
        draw_rate(ax, ks, rate, lo, hi, floor, cmap(i / max(1, n - 1)), f"c = {c} ({codes} codes)", marker="o",
                  ms=3, lw=1.3)
        theory_lo = th if theory_lo is None else [min(a, b) for a, b in zip(theory_lo, th)]
        theory_hi = th if theory_hi is None else [max(a, b) for a, b in zip(theory_hi, th)]
        ks_all = ks
    ax.fill_between(ks_all, theory_lo, theory_hi, color="black", alpha=0.15, lw=0,
                    label="theory: random payloads,\n4 N V(25, k) / 2^25 over the ten N")
    ax.plot(ks_all, theory_hi, "k--", lw=1)
    ax.plot(ks_all, theory_lo, "k--", lw=1)
    ax.set_yscale("log")
    ax.set_xticks(ks_all)
    ax.set_xlabel("bits corrected (maximum Hamming distance accepted)")
    ax.set_ylabel("false positives per candidate quad")
    ax.set_title(f"Fig. 6 reproduced: 25h9 by minimum complexity\n{quads:,} candidate quads from the Debian "
                 "photo corpus; 95 % Wilson intervals", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.plot([], [], "kv", mfc="none", label="none accepted (bar: 95 % upper bound)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    save(fig, os.path.join(results, "fig6_complexity.png"))


def fig7(results):
    cs, quads, floor, fig, ax = curve_plot(results, "fig7_codes.csv")
    for i, (scheme, (ks, rate, lo, hi, th, codes, _)) in enumerate(cs.items()):
        color = f"C{i}"
        draw_rate(ax, ks, rate, lo, hi, floor, color, f"{scheme} ({codes} codes)", marker="o", ms=3, lw=1.4)
        ax.plot(ks, th, color=color, ls=":", lw=1)
    ax.plot([], [], "k:", lw=1, label="dotted: random payloads (4 N V / 2^36)")
    ax.plot([], [], "kv", mfc="none", label="none accepted (bar: 95 % upper bound)")
    ax.set_yscale("log")
    ax.set_ylim(floor / 2, 1.5)
    ax.set_xlabel("bits corrected (maximum Hamming distance accepted)")
    ax.set_ylabel("false positives per candidate quad")
    ax.set_title(f"Fig. 7 reproduced: 36-bit coding systems\n{quads:,} candidate quads from the Debian photo "
                 "corpus; 95 % Wilson intervals", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, os.path.join(results, "fig7_codes.png"))


def detectors(results):
    rows = read(os.path.join(results, "fp_detectors.csv"))
    dets = list(OrderedDict.fromkeys(r["detector"] for r in rows))
    fams = list(OrderedDict.fromkeys(r["family"] for r in rows))
    subsets = [("still", "stills"), ("video-frame", "video frames")]
    fig, axes = plt.subplots(1, len(subsets), figsize=(11, 4.6), sharey=True)
    width = 0.8 / max(1, len(dets))
    floor = None
    for r in rows:
        if r["subset"] in ("still", "video-frame"):
            f = 0.3 / float(r["megapixels"])
            floor = f if floor is None else min(floor, f)
    for ax, (subset, title) in zip(axes, subsets):
        images = mp = 0
        for j, d in enumerate(dets):
            xs, ys, lo, hi, counts = [], [], [], [], []
            for i, fam in enumerate(fams):
                for r in rows:
                    if r["detector"] == d and r["family"] == fam and r["subset"] == subset:
                        xs.append(i + (j - (len(dets) - 1) / 2) * width)
                        y = float(r["per_megapixel"])
                        ys.append(max(y, floor))
                        lo.append(max(ys[-1] - max(float(r["per_megapixel_ci95_lo"]), floor), 0))
                        hi.append(max(float(r["per_megapixel_ci95_hi"]) - ys[-1], 0))
                        counts.append(r["detections"])
                        images, mp = int(r["images"]), float(r["megapixels"])
            ax.bar(xs, [y - floor / 2 for y in ys], width * 0.9, bottom=floor / 2, color=f"C{j}", label=d,
                   yerr=[lo, hi], capsize=2)
            for x, y, c in zip(xs, ys, counts):  # the count under each bar's top: 0 bars are stubs
                ax.annotate(c, (x, y), xytext=(0, -2), textcoords="offset points", ha="center", va="top",
                            fontsize=7, color="white" if int(c) else "black")
        ax.set_yscale("log")
        ax.set_xticks(range(len(fams)))
        ax.set_xticklabels(fams)
        ax.set_title(f"{title}: {images} images, {mp:.0f} Mpx", fontsize=10)
        ax.grid(True, axis="y", which="both", alpha=0.3)
    axes[0].set_ylabel("false detections per megapixel (95 % exact Poisson)")
    axes[0].legend(fontsize=8)
    fig.suptitle("Whole detectors at their defaults on the Debian photo corpus (no tags in it)", fontsize=11)
    fig.tight_layout()
    save(fig, os.path.join(results, "fp_detectors.png"))


def margin(results):
    rows = read(os.path.join(results, "margin_tradeoff.csv"))
    steps = read(os.path.join(results, "margin_tradeoff_steps.csv"))
    if not rows:
        sys.exit("plot_falsepos.py: margin_tradeoff.csv has no rows")
    fams = list(OrderedDict.fromkeys(r["family"] for r in rows))
    parts = [k[:-len("_frames")] for k in rows[0] if k.endswith("_frames")]
    fig, axes = plt.subplots(2, len(fams), figsize=(5.6 * len(fams), 8.4), squeeze=False)
    images = int(rows[0]["images"])
    floor = 0.3 / images
    for col, fam in enumerate(fams):
        fr = [r for r in rows if r["family"] == fam]
        th = [float(r["threshold"]) for r in fr]
        ax = axes[0][col]
        fp = [float(r["fp_per_image"]) for r in fr]
        fp_hi = [float(r["fp_per_image_ci95_hi"]) for r in fr]
        draw_rate(ax, th, fp, [float(r["fp_per_image_ci95_lo"]) for r in fr], fp_hi, floor, "C3",
                  "false detections per image", marker="o", ms=3, lw=1.4)
        ax.set_yscale("log")
        fp_lo = [float(r["fp_per_image_ci95_lo"]) for r in fr]
        bottom = floor if min(fp) <= 0 else min(x for x in fp_lo + fp if x > 0)
        ax.set_ylim(bottom / 2, max(fp_hi) * 3)
        ax.set_xlabel("minimum decision margin")
        ax.set_ylabel("false detections per corpus image (95 % exact Poisson)", color="C3")
        ax.grid(True, which="both", alpha=0.3)
        ax2 = ax.twinx()
        for i, p in enumerate(parts):
            rate = [float(r[p + "_rate"]) for r in fr]
            ax2.plot(th, rate, color=f"C{i}", marker=".", lw=1.2, label=f"ray-traced {p}: detection rate")
            ax2.fill_between(th, [float(r[p + "_rate_ci95_lo"]) for r in fr],
                             [float(r[p + "_rate_ci95_hi"]) for r in fr], color=f"C{i}", alpha=0.08, lw=0)
        ax2.set_ylim(0, 1.02)
        ax2.set_ylabel("detection rate of real tags (95 % Wilson)")
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = ax2.get_legend_handles_labels()
        ax2.legend(h1 + h2, l1 + l2, fontsize=7, loc="center left")
        ax.set_title(f"{fam}: {images} corpus images; ray-traced frames of {fam}", fontsize=10)
        # Below: the distance sweep's rate per distance at a few thresholds.
        ax = axes[1][col]
        shown = [t for t in sorted(set(th)) if round(t * 20) % 4 == 0]  # 0, 0.2, 0.4, ... when present
        cmap = plt.get_cmap("viridis")
        for i, t in enumerate(shown):
            st = [s for s in steps if s["family"] == fam and s["part"] == "distance" and float(s["threshold"]) == t]
            if not st:
                continue
            ax.plot([float(s["step"]) for s in st], [float(s["rate"]) for s in st], marker=".", lw=1.2,
                    color=cmap(i / max(1, len(shown) - 1)), label=f"margin >= {t:g}")
        ax.set_xlabel("distance (m; 1 m black square, 400 px focal length)")
        ax.set_ylabel("detection rate")
        ax.set_ylim(0, 1.02)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title(f"{fam}: distance sweep by minimum margin", fontsize=10)
    fig.suptitle("A minimum decision margin (beyond the paper): false detections saved, real detections lost",
                 fontsize=11)
    fig.tight_layout()
    save(fig, os.path.join(results, "margin_tradeoff.png"))


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    which = sys.argv[2:] or [w for w, f in (("fig6", "fig6_complexity.csv"), ("fig7", "fig7_codes.csv"),
                                            ("detectors", "fp_detectors.csv"),
                                            ("margin", "margin_tradeoff.csv"))
                             if os.path.exists(os.path.join(results, f))]
    for w in which:
        {"fig6": fig6, "fig7": fig7, "detectors": detectors, "margin": margin}[w](results)


if __name__ == "__main__":
    main()

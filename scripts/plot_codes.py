#!/usr/bin/python3
"""Plots Fig. 5 of the paper from results/fig5_hamming.csv: the distribution of Hamming distances
between all pairs of codewords (minimum over rotations), one line per coding system.
Usage: plot_codes.py RESULTS_DIR   (writes RESULTS_DIR/fig5_hamming.png atomically)"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    src = os.path.join(results, "fig5_hamming.csv")
    series = defaultdict(lambda: ([], [], []))
    labels = {}
    with open(src, newline="") as f:
        for row in csv.DictReader(f):
            xs, fr, cum = series[row["family"]]
            xs.append(int(row["distance"]))
            fr.append(float(row["fraction"]))
            labels[row["family"]] = f'{row["scheme"]} ({row["codes"]} codes)'
    if not series:
        sys.exit(f"plot_codes.py: {src} has no rows")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    for fam, (xs, fr, _) in series.items():
        pts = [(x, y) for x, y in zip(xs, fr) if y > 0]
        ax1.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=labels[fam])
        total, cum = 0.0, []
        for y in fr:
            total += y
            cum.append(total)
        cpts = [(x, y) for x, y in zip(xs, cum) if y > 0]
        ax2.step([p[0] for p in cpts], [p[1] for p in cpts], where="post", label=labels[fam])
    ax1.set_yscale("log")
    ax1.set_xlabel("Hamming distance (minimum over the 4 rotations)")
    ax1.set_ylabel("fraction of codeword pairs")
    ax1.set_title("Distances between all pairs of codewords")
    ax2.set_yscale("log")
    ax2.set_xlabel("Hamming distance d")
    ax2.set_ylabel("fraction of pairs at distance <= d")
    ax2.set_title("Cumulative: the close pairs that cause confusions")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.set_xlim(0, 36)
    ax1.legend(fontsize=7)
    fig.suptitle("Fig. 5 reproduced: Hamming distances of 36-bit (and smaller) codes")
    fig.tight_layout()
    out = os.path.join(results, "fig5_hamming.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()

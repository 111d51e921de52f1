#!/usr/bin/python3
"""Records the corpus and its extraction for make bench (issue 5, section 4):
  RESULTS/corpus_groups.csv      per group and kind: images, megapixels, candidate quads, packages, licences
  RESULTS/corpus_extraction.csv  per stage (build: fetch + unpack + decode + write PNGs; candidates: the
                                 quad stage and payload reads): images, megapixels, seconds, images/s, Mpx/s
The build row is replaced only when the build did work (a rebuild with everything in place does
nothing and measures nothing); otherwise the earlier measurement is kept.
Usage: corpus_stats.py RESULTS CORPUS BUILD_MS BUILD_DID_WORK(0|1) CANDIDATES_MS JOBS"""
import csv
import io
import os
import platform
import sys
import time
from collections import OrderedDict


def cpu():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def write_atomic(path, header, body):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(body)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(buf.getvalue())
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__.split("Usage: ")[1])
    results, corpus, build_ms, build_work, cand_ms, jobs = sys.argv[1:]
    with open(os.path.join(corpus, "corpus_candidates.tsv"), newline="") as f:
        index = list(csv.DictReader(f, delimiter="\t"))
    manifest = {}
    mpath = os.path.join(corpus, "manifest.tsv")
    if os.path.exists(mpath):
        with open(mpath, newline="") as f:
            for r in csv.DictReader(f, delimiter="\t"):
                manifest[r["file"]] = r
    groups = OrderedDict()
    for r in index:
        if r["status"] != "ok":
            continue
        g = groups.setdefault((r["group"], r["kind"]), {"images": 0, "mp": 0.0, "quads": 0, "pk": set(), "lic": set()})
        g["images"] += 1
        g["mp"] += int(r["width"]) * int(r["height"]) / 1e6
        g["quads"] += int(r["quads"])
        m = manifest.get(r["file"])
        if m:
            g["pk"].add(m["package"] + " " + m["version"])
            g["lic"].add(m["licence"])
    write_atomic(os.path.join(results, "corpus_groups.csv"),
                 ["group", "kind", "images", "megapixels", "candidate_quads", "packages", "licences"],
                 [[g, k, v["images"], f'{v["mp"]:.3f}', v["quads"], "; ".join(sorted(v["pk"])),
                   "; ".join(sorted(v["lic"]))] for (g, k), v in groups.items()])

    images = sum(1 for r in index if r["status"] == "ok")
    mp = sum(int(r["width"]) * int(r["height"]) / 1e6 for r in index if r["status"] == "ok")
    now = time.strftime("%Y-%m-%d %H:%M:%S")
    header = ["stage", "images", "megapixels", "seconds", "images_per_second", "megapixels_per_second", "jobs", "cpu",
              "measured"]

    def row(stage, ms):
        s = float(ms) / 1000
        return [stage, images, f"{mp:.2f}", f"{s:.1f}", f"{images / s:.3g}" if s > 0 else "",
                f"{mp / s:.3g}" if s > 0 else "", jobs, cpu(), now]

    out = os.path.join(results, "corpus_extraction.csv")
    old = {}
    if os.path.exists(out):
        with open(out, newline="") as f:
            for r in csv.DictReader(f):
                old[r["stage"]] = [r.get(h, "") for h in header]
    rows = []
    if build_work == "1":
        rows.append(row("build", build_ms))
    elif "build" in old:
        rows.append(old["build"])
    rows.append(row("candidates", cand_ms))
    write_atomic(out, header, rows)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Runs the libFuzzer targets of fuzz/ (built by `make fuzz` into BUILD/fuzz/fuzz_<name>) one after
the other, each for --seconds, and records every run in results/fuzz.csv.

Each target fuzzes a working corpus outside the repository, BUILD/corpus/<name>/ (new inputs are
written there; it persists across runs, so coverage accumulates), read together with the committed
seeds fuzz/corpus/<name>/ and crash regressions fuzz/regressions/<name>/. Crash, timeout, OOM and
leak inputs go to BUILD/artifacts/<name>/, the fuzzer's output to BUILD/logs/<name>-<stamp>.log.

results/fuzz.csv gets one row per target and run:
  date         UTC start of the run, ISO 8601
  target       fuzz target name (fuzz/fuzz_<target>.cpp)
  seconds      wall time of the run
  executions   inputs run (libFuzzer's stat::number_of_executed_units)
  coverage     coverage points ("cov:" of libFuzzer's last status line)
  features     coverage features ("ft:")
  corpus       inputs in the fuzzer's corpus at the end ("corp:")
  crashes      new crash-/timeout-/oom-/leak- files in BUILD/artifacts/<target>/
  status       ok, or the kind of the first finding (crash, timeout, oom, leak), or error (exit N)
The file is rewritten whole through a temporary file and a rename, so an interrupted run never
leaves it half-written. results/fuzz_summary.csv (same way) totals the rows per target: runs,
seconds, executions, the highest coverage and the crashes; it is printed at the end too.
"""
import argparse
import csv
import datetime
import io
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGETS = ["detector", "image_file", "family", "args", "manifest", "rcc", "candidates"]
FIELDS = ["date", "target", "seconds", "executions", "coverage", "features", "corpus", "crashes", "status"]
SUMMARY_FIELDS = ["target", "runs", "seconds", "executions", "max_coverage", "crashes"]
ARTIFACT_KINDS = ("crash-", "timeout-", "oom-", "leak-")


def write_atomic(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", newline="") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def to_csv(fields, rows):
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow(r)
    return out.getvalue()


def read_rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        r = csv.DictReader(f)
        if r.fieldnames != FIELDS:
            sys.exit(f"fuzz: {path} has the columns {r.fieldnames}, expected {FIELDS}; not overwriting it")
        return list(r)


def artifacts(folder):
    if not os.path.isdir(folder):
        return set()
    return {f for f in os.listdir(folder) if f.startswith(ARTIFACT_KINDS)}


def parse_log(text):
    """Executions, coverage, features and corpus size from libFuzzer's output."""
    stats = {"executions": "", "coverage": "", "features": "", "corpus": ""}
    m = re.findall(r"^stat::number_of_executed_units:\s*(\d+)", text, re.M)
    if m:
        stats["executions"] = m[-1]
    status = [line for line in text.splitlines() if re.match(r"^#\d+\s", line) and " cov: " in line]
    if status:
        last = status[-1]
        for key, name in (("coverage", "cov"), ("features", "ft"), ("corpus", "corp")):
            m = re.search(rf"\b{name}: (\d+)", last)
            if m:
                stats[key] = m.group(1)
        if not stats["executions"]:
            stats["executions"] = re.match(r"^#(\d+)", last).group(1)
    return stats


def run_target(build, name, seconds, extra):
    binary = os.path.join(build, "fuzz", f"fuzz_{name}")
    if not os.access(binary, os.X_OK):
        sys.exit(f"fuzz: {binary} not found; build it with `make fuzz` (cmake -DTAGBENCH_FUZZ=ON, clang)")
    work = os.path.join(build, "corpus", name)
    art = os.path.join(build, "artifacts", name)
    logs = os.path.join(build, "logs")
    for d in (work, art, logs):
        os.makedirs(d, exist_ok=True)
    dirs = [work] + [d for d in (os.path.join(ROOT, "fuzz", "corpus", name), os.path.join(ROOT, "fuzz", "regressions", name))
                     if os.path.isdir(d)]
    before = artifacts(art)
    start = datetime.datetime.now(datetime.timezone.utc)
    stamp = start.strftime("%Y%m%dT%H%M%SZ")
    log = os.path.join(logs, f"{name}-{stamp}.log")
    cmd = [binary, f"-max_total_time={seconds}", "-print_final_stats=1", f"-artifact_prefix={art}/",
           "-timeout=25", "-rss_limit_mb=2048", *extra, *dirs]
    print(f"fuzz: {name} for {seconds} s (log {os.path.relpath(log, ROOT)})", flush=True)
    t0 = time.monotonic()
    with open(log, "w") as f:
        rc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=build).returncode
    elapsed = time.monotonic() - t0
    with open(log, errors="replace") as f:
        stats = parse_log(f.read())
    found = sorted(artifacts(art) - before)
    if found:
        status = found[0].split("-", 1)[0]
    elif rc != 0:
        status = f"error (exit {rc})"
    else:
        status = "ok"
    for a in found:
        print(f"fuzz: {name}: FINDING {os.path.relpath(os.path.join(art, a), ROOT)}", flush=True)
    return {"date": start.strftime("%Y-%m-%dT%H:%M:%SZ"), "target": name, "seconds": str(round(elapsed)),
            **stats, "crashes": str(len(found)), "status": status}


def summary(rows):
    per = {}
    for r in rows:
        s = per.setdefault(r["target"], {"target": r["target"], "runs": 0, "seconds": 0, "executions": 0,
                                         "max_coverage": 0, "crashes": 0})
        s["runs"] += 1
        s["seconds"] += int(r["seconds"] or 0)
        s["executions"] += int(r["executions"] or 0)
        s["max_coverage"] = max(s["max_coverage"], int(r["coverage"] or 0))
        s["crashes"] += int(r["crashes"] or 0)
    order = [t for t in TARGETS if t in per] + sorted(t for t in per if t not in TARGETS)
    return [per[t] for t in order]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build-fuzz", help="the TAGBENCH_FUZZ build folder")
    ap.add_argument("--seconds", type=int, default=60, help="fuzzing time per target")
    ap.add_argument("--results", default=os.path.join(ROOT, "results", "fuzz.csv"))
    ap.add_argument("--libfuzzer-arg", action="append", default=[], help="passed on to every fuzzer")
    ap.add_argument("--summary-only", action="store_true",
                    help="only rewrite fuzz_summary.csv from the rows of fuzz.csv")
    ap.add_argument("targets", nargs="*", help=f"default: all ({' '.join(TARGETS)})")
    a = ap.parse_args()
    summary_path = os.path.join(os.path.dirname(a.results), "fuzz_summary.csv")
    if a.summary_only:
        write_atomic(summary_path, to_csv(SUMMARY_FIELDS, summary(read_rows(a.results))))
        return 0
    if a.seconds < 1:
        sys.exit("fuzz: --seconds must be at least 1")
    targets = a.targets or TARGETS
    for t in targets:
        if t not in TARGETS:
            sys.exit(f"fuzz: unknown target '{t}' (known: {' '.join(TARGETS)})")
    build = os.path.abspath(a.build)
    rows = read_rows(a.results)  # checked before any fuzzing, so a foreign file stops us early
    findings = 0
    for t in targets:
        row = run_target(build, t, a.seconds, a.libfuzzer_arg)
        findings += int(row["crashes"])
        rows = read_rows(a.results) + [row]  # re-read: another run may have appended meanwhile
        write_atomic(a.results, to_csv(FIELDS, rows))
        # The totals after every target, so an interrupted session leaves the two files consistent.
        write_atomic(summary_path, to_csv(SUMMARY_FIELDS, summary(rows)))
        print(f"fuzz: {t}: {row['seconds']} s, {row['executions']} executions, cov {row['coverage']}, "
              f"ft {row['features']}, corpus {row['corpus']}, {row['crashes']} crashes, {row['status']}", flush=True)
    summ = summary(rows)
    print("\nfuzz: totals over all recorded runs (results/fuzz_summary.csv)")
    print(f"{'target':<12} {'runs':>5} {'seconds':>8} {'executions':>12} {'max cov':>8} {'crashes':>8}")
    for s in summ:
        print(f"{s['target']:<12} {s['runs']:>5} {s['seconds']:>8} {s['executions']:>12} {s['max_coverage']:>8} "
              f"{s['crashes']:>8}")
    if findings:
        print(f"\nfuzz: {findings} finding(s); inputs under {os.path.relpath(build, ROOT)}/artifacts/", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Converts a Google Benchmark JSON report into a CSV with the machine's context on every row.
Usage: bench_to_csv.py REPORT.json OUT.csv   (OUT written atomically)"""
import csv
import json
import os
import sys


def main():
    report, out = sys.argv[1], sys.argv[2]
    with open(report) as f:
        data = json.load(f)
    ctx = data.get("context", {})
    base = ["name", "iterations", "real_time", "cpu_time", "time_unit", "items_per_second", "label"]
    extra = sorted({k for b in data["benchmarks"] for k in b if k not in base and k not in (
        "run_name", "run_type", "repetitions", "repetition_index", "threads", "family_index",
        "per_family_instance_index", "aggregate_name", "aggregate_unit")})
    cols = base + extra + ["host_cpus", "mhz_per_cpu", "cpu_model", "library_build_type", "date"]
    tmp = out + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for b in data["benchmarks"]:
            row = [b.get(c, "") for c in base + extra]
            row += [ctx.get("num_cpus", ""), ctx.get("mhz_per_cpu", ""), os.environ.get("TAGBENCH_CPU", ""),
                    ctx.get("library_build_type", ""), ctx.get("date", "")]
            w.writerow(row)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()

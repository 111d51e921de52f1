#!/usr/bin/env python3
"""libtagbench.so exports the tagbench namespace and nothing else (detector/libtagbench.map).

Usage: exported_symbols.py LIBRARY
Lists the library's defined dynamic symbols with `nm -DC --defined-only` and fails (exit 1, one line
per offending symbol) when one outside the namespace is exported (a std:: or Eigen template instance,
say: the version script no longer applies), or when a symbol a program needs is missing (the script
hides too much). Linker-defined markers (_end, _edata, __bss_start, _init, _fini) are not symbols of
the code and are ignored.
"""
import re
import subprocess
import sys

LINKER_MARKERS = {"_end", "_edata", "__bss_start", "_init", "_fini"}
ALLOWED = re.compile(r"^(?:(?:typeinfo for|typeinfo name for|vtable for|VTT for) )?tagbench::")
# What every program of the README's quick starts calls, and the type information a `catch` or a
# dynamic_cast across the library boundary needs.
REQUIRED = [
    "tagbench::Detector::Detector(",
    "tagbench::Detector::detect(",
    "tagbench::DetectorWorkspace::DetectorWorkspace(",
    "tagbench::DetectorOptions::paper()",
    "tagbench::DetectorOptions::validate() const",
    "tagbench::load_family(",
    "tagbench::builtin_family_names",
]


def main(argv):
    if len(argv) != 2:
        print("usage: exported_symbols.py LIBRARY", file=sys.stderr)
        return 2
    lib = argv[1]
    try:
        out = subprocess.run(["nm", "-DC", "--defined-only", lib], check=True,
                             capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"exported_symbols.py: {lib}: nm failed: {e}", file=sys.stderr)
        return 2
    names = []
    for line in out.splitlines():
        parts = line.split(maxsplit=2)
        if len(parts) == 3:
            names.append(parts[2])
    bad = [n for n in names if n not in LINKER_MARKERS and not ALLOWED.match(n)]
    missing = [r for r in REQUIRED if not any(n.startswith(r) for n in names)]
    for n in bad:
        print(f"{lib}: exported outside the tagbench namespace: {n}")
    for r in missing:
        print(f"{lib}: not exported: {r}...")
    ours = sum(1 for n in names if ALLOWED.match(n))
    print(f"{lib}: {len(names)} defined dynamic symbols, {ours} in the tagbench namespace, "
          f"{len(bad)} outside it, {len(missing)} required missing")
    return 1 if bad or missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

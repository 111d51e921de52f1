"""Shared pieces of the README table generators (update_readme.py and its modules)."""
import csv


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def table(header, body):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in body]
    return "\n".join(out)

"""Writes a list of dicts as CSV. Rows may have different keys (a method's
stage columns, a sweep's extra columns): the header is their union in the
order first seen, and a missing value is left empty."""
import csv


def write_rows(path, rows):
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)

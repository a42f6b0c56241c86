#!/usr/bin/env python3
"""Compares two experiment output folders (run_experiment --out DIR) bitwise, timing aside.

    scripts/compare_results.py BEFORE AFTER [--rename OLD=NEW ...]

BEFORE and AFTER are either one experiment's folder or folders of experiment folders (each
subfolder with a summary.csv or raw/trials.csv is compared with its namesake). Compared:
raw/trials.csv, raw/curves.csv, summary.csv, curves.csv, summary.md, summary.tex and
config.resolved.json (a timing column is a "time_*" column, or the cells of a "time_*"
table metric). --rename maps a CSV column (and column-name prefix, e.g. a metric whose
_mean, _median ... columns follow) of BEFORE to its name in AFTER, for deliberate renames.
Prints one line per difference and exits 1 when there is any.
"""
import csv
import io
import json
import os
import sys

CSV_FILES = ["raw/trials.csv", "raw/curves.csv", "summary.csv", "curves.csv"]
TABLE_FILES = {"summary.md": "|", "summary.tex": "&"}


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


RENAMES = {}


def renamed(name):
    for old, new in RENAMES.items():
        if name == old or name.startswith(old + "_"):
            return new + name[len(old):]
    return name


def csv_rows(path, rename=False):
    rows = list(csv.reader(io.StringIO(read(path))))
    if not rows:
        return [], []
    if rename:
        rows[0] = [renamed(c) for c in rows[0]]
    keep = [i for i, name in enumerate(rows[0]) if not name.startswith("time_")]
    return [rows[0][i] for i in keep], [[row[i] for i in keep] for row in rows[1:]]


def table_lines(path, separator, config):
    """Lines with the cells of timing metrics masked: the tables have the method, the sweep
    values and the trials, then three cells (mean, median, interval) per table metric."""
    lead = 2 + len(config.get("sweep", []))
    if separator == "|":
        lead += 1  # the empty cell before the first '|'
    timed = {lead + 3 * i + k for i, m in enumerate(config.get("table_metrics", [])) if m.startswith("time_")
             for k in range(3)}
    out = []
    for line in read(path).splitlines():
        cells = line.split(separator)
        if len(cells) >= lead + 3:
            cells = ["<time>" if i in timed else c for i, c in enumerate(cells)]
        out.append(separator.join(cells))
    return out


def compare_experiment(before, after, name):
    differences = []
    for rel in CSV_FILES:
        a, b = os.path.join(before, rel), os.path.join(after, rel)
        if not os.path.exists(a) and not os.path.exists(b):
            continue
        if not (os.path.exists(a) and os.path.exists(b)):
            differences.append(f"{name}/{rel}: present on one side only")
            continue
        (ha, ra), (hb, rb) = csv_rows(a, rename=True), csv_rows(b)
        if ha != hb:
            differences.append(f"{name}/{rel}: header differs: {sorted(set(ha) ^ set(hb))}")
            continue
        if len(ra) != len(rb):
            differences.append(f"{name}/{rel}: {len(ra)} rows against {len(rb)}")
        for k, (x, y) in enumerate(zip(ra, rb)):
            if x != y:
                cols = [ha[i] for i in range(len(x)) if x[i] != y[i]]
                differences.append(f"{name}/{rel}: row {k + 1} differs in {cols[:6]}{' ...' if len(cols) > 6 else ''}")
    config_path = os.path.join(before, "config.resolved.json")
    config = json.loads(read(config_path)) if os.path.exists(config_path) else {}
    for rel, separator in TABLE_FILES.items():
        a, b = os.path.join(before, rel), os.path.join(after, rel)
        if os.path.exists(a) and os.path.exists(b):
            la, lb = table_lines(a, separator, config), table_lines(b, separator, config)
            for k, (x, y) in enumerate(zip(la, lb)):
                if x != y:
                    differences.append(f"{name}/{rel}: line {k + 1} differs")
            if len(la) != len(lb):
                differences.append(f"{name}/{rel}: {len(la)} lines against {len(lb)}")
    a, b = os.path.join(before, "config.resolved.json"), os.path.join(after, "config.resolved.json")
    if os.path.exists(a) and os.path.exists(b) and json.loads(read(a)) != json.loads(read(b)):
        differences.append(f"{name}/config.resolved.json differs")
    return differences


def is_experiment(path):
    return os.path.exists(os.path.join(path, "summary.csv")) or os.path.exists(os.path.join(path, "raw/trials.csv"))


def main():
    args = sys.argv[1:]
    while "--rename" in args:
        i = args.index("--rename")
        old, new = args[i + 1].split("=", 1)
        RENAMES[old] = new
        del args[i:i + 2]
    if len(args) != 2:
        print(__doc__)
        return 2
    before, after = args
    if is_experiment(before):
        pairs = [(before, after, os.path.basename(os.path.normpath(before)))]
    else:
        pairs = [(os.path.join(before, n), os.path.join(after, n), n) for n in sorted(os.listdir(before))
                 if is_experiment(os.path.join(before, n))]
    differences = []
    for a, b, name in pairs:
        if not is_experiment(b):
            differences.append(f"{name}: missing in {after}")
            continue
        differences += compare_experiment(a, b, name)
    for line in differences:
        print(line)
    print(f"{len(pairs)} experiments compared, {len(differences)} differences")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())

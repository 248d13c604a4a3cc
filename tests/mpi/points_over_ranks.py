"""A sweep (friction_sweep) or scan (peierls_scan) over MPI ranks against the same run in one
process (issue 26, part 3): every point is computed by one rank with the serial code, so the
table must be the serial table, every cell but the run's own (wall times) identical, and so must
each point's files that hold no time.

Usage: points_over_ranks.py --np N --reference DIR --out DIR --table NAME [--ignore COL,...]
           [--point-file NAME] [--require-other-rank] -- MPIEXEC [FLAGS...] TOOL ARGS...
The command after "--" is run with "--out DIR" appended, after DIR is removed.
"""
import argparse
import csv
import pathlib
import re
import shutil
import subprocess
import sys


def read_table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--np", type=int, required=True)
    p.add_argument("--reference", type=pathlib.Path, required=True)
    p.add_argument("--out", type=pathlib.Path, required=True)
    p.add_argument("--table", required=True)
    p.add_argument("--ignore", default="", help="columns that differ between runs (times)")
    p.add_argument("--point-file", default="", help="a file of each point folder to compare")
    p.add_argument("--require-other-rank", action="store_true",
                   help="fail unless a rank other than 0 computed a point")
    p.add_argument("command", nargs="+")
    a = p.parse_args()

    shutil.rmtree(a.out, ignore_errors=True)
    run = subprocess.run(a.command + ["--out", str(a.out)], capture_output=True, text=True,
                         timeout=110)
    sys.stderr.write(run.stderr)
    sys.stdout.write(run.stdout)
    if run.returncode != 0:
        sys.exit(f"FAIL: exit status {run.returncode}")

    # Rank 0 alone prints the report: its "results:" line once, whatever the number of ranks.
    results = [line for line in run.stdout.splitlines() if line.startswith("results:")]
    if len(results) != 1:
        sys.exit(f"FAIL: {len(results)} 'results:' lines on standard output, expected 1")

    columns, rows = read_table(a.reference / a.table)
    out_columns, out_rows = read_table(a.out / a.table)
    if out_columns != columns:
        sys.exit(f"FAIL: columns {out_columns} differ from the serial run's {columns}")
    if len(out_rows) != len(rows) or not rows:
        sys.exit(f"FAIL: {len(out_rows)} rows against the serial run's {len(rows)}")
    ignored = [c for c in a.ignore.split(",") if c]
    for c in ignored:
        if c not in columns:
            sys.exit(f"FAIL: no column {c} to ignore in {a.table}")
    compared = [j for j, c in enumerate(columns) if c not in ignored]
    for i, (r, o) in enumerate(zip(rows, out_rows)):
        for j in compared:
            if r[j] != o[j]:
                sys.exit(f"FAIL: row {i + 1}, column {columns[j]}: {o[j]!r} over {a.np} ranks, "
                         f"{r[j]!r} in one process")

    points = 0
    if a.point_file:
        for ref in sorted((a.reference / "points").glob("*/" + a.point_file)):
            other = a.out / "points" / ref.parent.name / a.point_file
            if not other.is_file() or other.read_bytes() != ref.read_bytes():
                sys.exit(f"FAIL: {other} is missing or differs from {ref}")
            points += 1
        if points != len(rows):
            sys.exit(f"FAIL: {points} point folders with {a.point_file}, {len(rows)} rows")

    ranks = sorted({int(r) for r in re.findall(r"\] .* on rank (\d+)$", run.stderr, re.M)})
    if a.np > 1 and a.require_other_rank and ranks in ([], [0]):
        sys.exit(f"FAIL: every point ran on rank 0 (ranks seen: {ranks})")
    print(f"{len(rows)} rows of {a.table} identical to the serial run's in {len(compared)} of "
          f"{len(columns)} columns (not compared: {', '.join(ignored) or 'none'})"
          + (f", {points} points' {a.point_file} byte for byte" if a.point_file else "")
          + f"; {a.np} rank(s), points computed on ranks {ranks or [0]}")


if __name__ == "__main__":
    main()

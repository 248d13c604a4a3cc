#!/usr/bin/env python3
"""The held loop's tables of data/reference/regime3_R800.md from one track_loops run.

Usage: scripts/front_tables.py <track_loops --out folder>

The folder holds `track_loops <slipN_before.nc> <slipN_after.nc> ... --profiles --front
--peierls <13-angle scan> --out <folder>` over the states around each slip (friction_sweep
--largest-slip's latest_slip_before.nc and latest_slip_after.nc, copied at every slip). Every
number printed is the tool's; this only lays them out:

1. the stress the loop's cores hold where they cross the axes (cores_NNNN.csv), per state
   after a slip: the edge ends along x, a screw side along y, against the weakest scanned
   direction's Peierls stress there;
2. where the front moved at each slip (front.moves in lines.json, front_moves_NNNN.csv) and
   what it held there just before, against the weakest direction's Peierls stress, with the
   whole front's quantiles in the state before (front.lines).
"""
import csv
import json
import pathlib
import re
import sys


def slip_of(name):
    m = re.search(r"slip_?(\d+)_(before|after)", name)
    return (int(m.group(1)), m.group(2)) if m else (None, None)


def main(folder):
    folder = pathlib.Path(folder)
    frames = json.loads((folder / "lines.json").read_text())["frames"]

    print("| slip | Dx (d) | sites | edge ends x- / x+: held (G) | at x - Dx (d) | held / weakest "
          "tau_P | screw sides: held (G) | at \\|y\\| (d) | held / weakest tau_P |")
    print("|---|---|---|---|---|---|---|---|---|")
    for f in frames:
        slip, when = slip_of(f["file"])
        prof = f.get("profiles")
        if prof is None or when != "after":
            continue
        x = [c for c in prof["x"]["cores"] if c["kind"] == "loop" and c.get("resolved")]
        y = [c for c in prof["y"]["cores"] if c["kind"] == "loop" and c.get("resolved")]
        if len(x) != 2 or not y:
            continue
        x.sort(key=lambda c: c["position"])
        side = max(y, key=lambda c: c["position"])
        held = " / ".join(f"{abs(c['stress']):.5f}" for c in x)
        where = " / ".join(f"{c['position']:.1f}" for c in x)
        ratio = " / ".join(f"{abs(c['stress']) / c['tau_P_weakest']:.3f}" for c in x)
        moved = (f.get("front") or {}).get("moves", {}).get("moved_sites", "")
        print(f"| {slip} | {f['Dx']:.5f} | {moved} | {held} | {where} | {ratio} "
              f"| {abs(side['stress']):.5f} "
              f"| {side['position']:.1f} | {abs(side['stress']) / side['tau_P_weakest']:.3f} |")
    print()

    print("| slip | sites | where the front moved (polar, deg) | held / weakest tau_P there: "
          "mixed and edge (> 30 deg) | near screw (< 30 deg) | whole front before: median, "
          "90%, max of held / weakest |")
    print("|---|---|---|---|---|---|")
    for f in frames:
        slip, when = slip_of(f["file"])
        front = f.get("front")
        if not front or "moves" not in front or when != "after":
            continue
        m = front["moves"]
        # The held loop: the loop of the earlier front with the most resolved points.
        loops = [line for line in frames[m["since_frame"]]["front"]["lines"]
                 if line["kind"] == "loop" and "weakest_ratio_median" in line]
        if not loops:
            continue
        before = max(loops, key=lambda line: line["resolved_points"])
        with open(folder / m["table"], newline="") as table:
            rows = list(csv.DictReader(table))
        # Runs of points along the line (the table is in order along it), 12 d apart at most.
        runs, cur = [], []
        for k, r in enumerate(rows):
            if cur and float(r["arc"]) - float(rows[cur[-1]]["arc"]) > 12.0:
                runs.append(cur)
                cur = []
            cur.append(k)
        if cur:
            runs.append(cur)
        polar = [float(r["polar_deg"]) for r in rows]
        where = ", ".join(f"{polar[r[0]]:+.0f}..{polar[r[-1]]:+.0f}" if len(r) > 1
                          else f"{polar[r[0]]:+.0f}" for r in runs)

        def span(key):
            v = m[key]
            return f"{v[0]:.2f}-{v[1]:.2f}" if v else "-"

        print(f"| {slip} | {m['moved_sites']} | {where} | {span('held_over_weakest_mixed_edge')} "
              f"| {span('held_over_weakest_near_screw')} | {before['weakest_ratio_median']:.3f}, "
              f"{before['weakest_ratio_p90']:.3f}, {before['weakest_ratio_max']:.3f} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

#!/usr/bin/env python3
"""Markdown table of path_check.json files (bench/run_path_tier.sh): per scene and solver, the
cost of relaxing the bracketed slip and whether it ends in the flow's minimum."""
import json
import sys


def main(paths):
    print("| a | R | slip | a/b_core^0 | solver | iterations | GF + filter | slipped | "
          "registry differences | abs(dFx)/Fx | loops (area, d^2) | same minimum as the flow |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for path in paths:
        with open(path) as f:
            j = json.load(f)
        head = f"| {j['a']:g} | {j['R']:g} | {j['slip_event']} | {j['a_over_bcore0']:.1f}"
        for name, step, cmp, lines in (
            ["flow (reference)", j["flow"], None, j.get("flow_lines")],
            ["flow, tolerance/2", j["flow_half_tolerance"], j["flow_half_against_flow"], None],
        ) + tuple([r["solver"], r["step"], r["against_flow"], r.get("lines")]
                  for r in j["solvers"]):
            cost = step["gf_applications"] + step["filter_applications"]
            same = "reference" if cmp is None else ("yes" if cmp["same_minimum"] else "no")
            diff = "" if cmp is None else str(cmp["registry_differences"])
            dfx = "" if cmp is None else f"{cmp['relative_Fx']:.1e}"
            loops = "" if lines is None else f"{lines['loops']} ({lines['loop_area']:.0f})"
            print(f"{head} | {name} | {step['iterations']} | {cost} | {step['slipped_sites']} | "
                  f"{diff} | {dfx} | {loops} | {same} |")
    if paths:
        with open(paths[0]) as f:
            p = json.load(f)["provenance"]
        print(f"\nProvenance of the first file: {json.dumps(p)}")


if __name__ == "__main__":
    main(sys.argv[1:])

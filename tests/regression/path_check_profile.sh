#!/usr/bin/env bash
# Regression tier: path_check on a small slip (a = 16 d, R = 535 d: 800 sites slip together) with
# --flow-profile. Its table says every solver ends in the flow's minimum, and it writes one
# profile per flow (the reference and flow/interface, none for lbfgs). A profile has one row per
# accepted step with counts that only grow, ends within the force tolerance, and its last GF
# count is within the relaxation's (which also counts bringing the state to Dx and u = G f at the
# end). Usage: path_check_profile.sh PATH_CHECK OUT
set -euo pipefail
tool=$1 out=$2
rm -rf "$out"
"$tool" --a 16 --R 535 --slip 1 --solvers flow/interface lbfgs/auto --flow-profile --out "$out" \
  >"$out.log" 2>&1 || { cat "$out.log"; exit 1; }
fail() { echo "path_check_profile: $*"; cat "$out.log"; exit 1; }
[ "$(grep -c ' yes ' "$out.log")" -eq 3 ] || fail "not every solver in the flow's minimum"
[ -f "$out/flow_profile.csv" ] || fail "no flow_profile.csv"
[ -f "$out/flow_profile_flow_interface_0.001.csv" ] || fail "no profile of flow/interface"
[ "$(ls "$out"/flow_profile*.csv | wc -l)" -eq 2 ] || fail "a profile of a solver that is not a flow"
python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
j = json.load(open(f"{out}/path_check.json"))
runs = {"flow_profile.csv": j["flow"], "flow_profile_flow_interface_0.001.csv": j["solvers"][0]["step"]}
for name, step in runs.items():
    rows = list(csv.DictReader(open(f"{out}/{name}")))
    assert rows and list(rows[0]) == ["iteration", "gf", "filter", "step", "radius", "max_speed",
                                      "max_residual", "max_move", "moved"], name
    for a, b in zip(rows, rows[1:]):
        assert int(b["iteration"]) > int(a["iteration"]) and int(b["gf"]) > int(a["gf"]), name
    last = rows[-1]
    assert int(last["gf"]) <= step["gf_applications"] <= int(last["gf"]) + 4, (name, last, step)
    assert int(last["filter"]) <= step["filter_applications"], name
    assert (int(last["filter"]) > 0) == name.endswith("0.001.csv"), name
    assert int(last["moved"]) > 0, name  # the slip moved sites by more than d/2
    if name == "flow_profile.csv":  # the G metric: max |P r| is max |r|
        assert float(last["max_residual"]) <= j["force_tolerance"], last
    print(f"{name}: {len(rows)} steps, GF {last['gf']} of {step['gf_applications']}")
PY

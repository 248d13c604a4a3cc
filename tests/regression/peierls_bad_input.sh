#!/usr/bin/env bash
# peierls_scan rejects bad scenes and flags before any work: exit status 2 and a message that
# names the offending key or flag. Usage: peierls_bad_input.sh <peierls_scan> <work dir>
set -u
tool="$1"
dir="$2"
rm -rf "$dir" && mkdir -p "$dir"
fail=0
check() {  # check <name> <expected text> <args...>
  local name="$1" expect="$2"
  shift 2
  local msg rc
  msg=$("$tool" "$@" --out "$dir/out" 2>&1 >/dev/null)
  rc=$?
  if [ $rc -ne 2 ] || ! grep -qF -- "$expect" <<<"$msg"; then
    echo "FAIL $name: rc=$rc, expected '$expect' in: $msg"
    fail=1
  else
    echo "ok   $name: ${msg%%$'\n'*}"
  fi
}
scene() {  # scene <name> <toml text>: writes a scene file, prints its path
  printf '%s\n' "$2" > "$dir/$1.toml"
  echo "$dir/$1.toml"
}
check flag_b_core_negative "--b-core" --b-core -1
check flag_b_core_nan "--b-core" --b-core nan
check flag_theta_range "--theta" --theta 120
check flag_L_small "--L" --L 4
check flag_model "--model" --model fancy
check flag_nu "--nu" --nu 0.7
check flag_precision "--precision" --precision 0
check flag_tolerance "--tolerance" --tolerance inf
check flag_unknown "--frobnicate" --frobnicate=3
check angle_not_offered "offered" --L 16 --theta 63.4
check L_odd "cell.L" --L 255
check scene_unknown_key "scan.bogus" "$(scene unknown '[scan]
bogus = 1')"
check scene_wrong_type "cell.L" "$(scene type '[cell]
L = "big"')"
check scene_model "cell.model" "$(scene model '[cell]
model = "huge"')"
check scene_b_core "scan.b_core" "$(scene bcore '[scan]
b_core = [0]')"
check scene_nu "material.nu" "$(scene nu '[material]
nu = nan')"
check scene_missing "scene" "$dir/no_such_scene.toml"
check flag_L_tolerance "--L-tolerance" --L-tolerance -0.1
check flag_L_tolerance_one "cell.L_tolerance" --L-tolerance 1
check flag_max_L "--max-L" --max-L 100000
check scene_b_core_empty "scan.b_core" "$(scene bcore_empty '[scan]
b_core = []')"
check scene_theta_empty "scan.theta" "$(scene theta_empty '[scan]
theta = []')"
check scene_fit_window "fit.b_min" "$(scene fit_window '[fit]
b_min = 6
b_max = 2')"
check scene_L_tolerance "cell.L_tolerance" "$(scene L_tolerance '[cell]
L_tolerance = 2')"
ASPERITY_MEMORY_GIB=1 check full_cell_memory "GiB of memory" --model full --L 2048 --L-tolerance 0
exit $fail

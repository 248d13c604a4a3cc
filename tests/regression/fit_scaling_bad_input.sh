#!/usr/bin/env bash
# Regression tier: fit_scaling refuses bad input before any work, with exit status 2 and a
# message that names the cause: missing or foreign tables, a missing Regime III law, options
# out of range, damaged peierls_scan summaries (three of them), mixed alpha, a point given
# twice, a forecast without its pair or of an adhesive-only set.
# Usage: fit_scaling_bad_input.sh FIT_SCALING REFERENCE_DIR WORK_DIR
set -u
fs=$1 ref=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir"
k="--k1 2 --k2 1.8"
t="$ref/sweep_R535.csv"
fit='{"fits": {"edge": {"valid": true, "k1": 2.3, "k1_error": 0.1, "k2": 1.8, "k2_error": 0.01, '
echo "$fit"'"window_b_core": []}}}' >"$dir/empty_window.json"
echo "$fit"'"window_b_core": [6, 2]}}}' >"$dir/reversed_window.json"
echo '{"fits": {"edge": {"valid": true, "k1": "big"}}}' >"$dir/k1_text.json"
echo "$fit"'"window_b_core": [2, 6], "k1_k2_correlation": 1.5}}}' >"$dir/correlation.json"
sed 's/,535,0.7,0.5,/,536,0.6,0.5,/' "$t" >"$dir/alpha06.csv"
echo "$fit"'"window_b_core": [2, 6]}}}' >"$dir/law.json"

failures=0 cases=0
# check EXPECTED ARGS...: exit 2 and EXPECTED in the message.
check() {
  local expected=$1 msg rc
  shift
  cases=$((cases + 1))
  msg=$("$fs" "$@" --out "$dir/out" 2>&1 >/dev/null)
  rc=$?
  if [ "$rc" -ne 2 ] || ! grep -qF -- "$expected" <<<"$msg"; then
    echo "FAIL: $*: exit $rc, expected 2 and '$expected' in: $msg"
    failures=$((failures + 1))
  else
    echo "ok: $*: $msg"
  fi
}
check "missing.csv: no such sweep table" "$dir/missing.csv" $k
check "not a friction_sweep table (no column 'a')" "$ref/peierls_L128.csv" $k
check "--peierls or both --k1 and --k2 are required" "$t"
check "window = [5]: allowed: two values" "$t" $k --window 5
check "--f-P: f_P = 0" "$t" $k --f-P 0
check "fewer than 2 points in the given window" "$t" $k --window 1e3,1e4
check "window_b_core = []: not a pair" "$t" --peierls "$dir/empty_window.json"
check "window_b_core = [6,2]: b_min must be below b_max" "$t" --peierls "$dir/reversed_window.json"
check "fits.edge.k1 = \"big\"" "$t" --peierls "$dir/k1_text.json"
check "k1_k2_correlation = 1.5: not a number in [-1, 1]" "$t" --peierls "$dir/correlation.json"
check "k1_k2_correlation: only with both k1 and k2" "$t" --peierls "$dir/correlation.json" \
  --k1-k2-correlation 0.5
check "alpha = 0.6 differs" "$t" "$dir/alpha06.csv" $k
check "give --k1 and --k2 together" "$t" --peierls "$dir/law.json" --k1 2
check "--peierls or both --k1 and --k2 are required" "$t" --k2 1.8
check "give each point once" "$t" "$t" $k
check "forecast_R and forecast_a: give both or neither" "$t" $k --forecast-R 800
check "--forecast-a: forecast_a = [0]" "$t" $k --forecast-R 800 --forecast-a 0
check "forecast_R = [800, 800]: a value is given twice" "$t" $k --forecast-R 800,800 \
  --forecast-a 300
check "no table is Hertz" "$ref/adhesive_tau0p2.csv" --forecast-R 800 --forecast-a 300
echo "$((cases - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]

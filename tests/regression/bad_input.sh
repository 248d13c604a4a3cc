#!/usr/bin/env bash
# Regression tier: bad scenes and flags are rejected before any work, with exit status 2 and a
# message that names the offending key or flag. Usage: bad_input.sh BIN_DIR WORK_DIR
set -uo pipefail
bin=$1
work=$2
rm -rf "$work" && mkdir -p "$work"
cases=0
failures=0

# check TOOL EXPECTED ARGS...: TOOL must exit 2 and print EXPECTED on stderr.
check() {
  local tool=$1 expected=$2
  shift 2
  cases=$((cases + 1))
  local err rc
  err=$("$bin/$tool" "$@" --out "$work/out" 2>&1 >/dev/null)
  rc=$?
  if [ "$rc" -ne 2 ] || ! grep -qF -- "$expected" <<<"$err"; then
    echo "FAIL: $tool $* -> exit $rc, expected 2 and '$expected' in: $err"
    failures=$((failures + 1))
  fi
}

# scene NAME: writes standard input to $work/NAME.toml and prints the path.
scene() {
  cat >"$work/$1.toml"
  echo "$work/$1.toml"
}

cs=contact_slide
check $cs "contact.radius" "$(scene s1 <<<$'[contact]\nradius = 5')"
check $cs "contact.a" "$(scene s2 <<<$'[contact]\na = -3')"
check $cs "contact.a" "$(scene s3 <<<$'[contact]\na = "abc"')"
check $cs "contact.a" "$(scene s4 <<<$'[contact]\na = nan')"
check $cs "contact.a" "$(scene s5 <<<$'[contact]\na = inf')"
check $cs "contact.R" "$(scene s6 <<<$'[contact]\nR = 0')"
check $cs "contact.alpha" "$(scene s7 <<<$'[contact]\nalpha = 0')"
check $cs "contact.a" "$(scene s8 <<<$'[contact]\na = 600\nR = 535')"
check $cs "material.nu" "$(scene s9 <<<$'[material]\nnu = 0.6')"
check $cs "material.G" "$(scene s10 <<<$'[material]\nG = -1')"
check $cs "slide.protocol" "$(scene s11 <<<$'[slide]\nprotocol = "fast"')"
check $cs "slide.step" "$(scene s12 <<<$'[slide]\nstep = 0')"
check $cs "slide.max_step" "$(scene s13 <<<$'[slide]\nmax_step = 2')"
check $cs "slide.min_step" "$(scene s14 <<<$'[slide]\nmax_step = 0.2\nmin_step = 0.3')"
check $cs "slide.distance" "$(scene s15 <<<$'[slide]\ndistance = -1')"
check $cs "slide.slips_to_stop" "$(scene s16 <<<$'[slide]\nslips_to_stop = 0')"
check $cs "slide.path_frame_every" "$(scene s17 <<<$'[slide]\npath_frame_every = -5')"
check $cs "solver.method" "$(scene s18 <<<$'[solver]\nmethod = "steepest"')"
check $cs "solver.tolerance" "$(scene s19 <<<$'[solver]\ntolerance = 0')"
check $cs "solver.max_iterations" "$(scene s20 <<<$'[solver]\nmax_iterations = 0')"
check $cs "solver.memory" "$(scene s21 <<<$'[solver]\nmemory = 0')"
check $cs "solver.max_displacement" "$(scene s22 <<<$'[solver]\nmax_displacement = 1')"
check $cs "solver.preconditioner" "$(scene s22b <<<$'[solver]\npreconditioner = "jacobi"')"
check $cs "solver.flow_tolerance" "$(scene s22c <<<$'[solver]\nflow_tolerance = 0')"
check $cs "solver.flow_scheme" "$(scene s22d <<<$'[solver]\nflow_scheme = "rk4"')"
check $cs "solver.slip_method" "$(scene s22e <<<$'[solver]\nslip_method = "bfgs"')"
check $cs "solver.slip_preconditioner" "$(scene s22f <<<$'[solver]\nslip_preconditioner = "x"')"
check $cs "--slip-solver" --slip-solver bfgs
# Slips are relaxed by a path-faithful solver (issue 21): lbfgs, cg and newton are not offered.
check $cs "solver.slip_method" "$(scene s22g <<<$'[solver]\nslip_method = "lbfgs"')"
check $cs "solver.slip_method" "$(scene s22h <<<$'[solver]\nslip_method = "same"')"
check $cs "solver.slip_method" "$(scene s22i <<<$'[solver]\nmethod = "cg"\nslip_method = "same"')"
check $cs 'with /' --slip-solver same
check $cs "--slip-solver" --slip-solver newton
check $cs 'solver.slip_method = "same" with --solver = "cg"' --solver cg "$(scene s22j <<<$'[solver]\nmethod = "flow"\nslip_method = "same"')"
check $cs 's22k.toml: solver.slip_method = "same" with solver.method = "lbfgs"' "$(scene s22k <<<$'[solver]\nslip_method = "same"')"
# The pair is checked after the flags, so a flag mends a scene's pair instead of being refused
# with it (a tiny slide: a = 5 d, 0.1 d, well under a second).
cases=$((cases + 1))
mend=$(scene s22m <<<$'[solver]\nmethod = "cg"\nslip_method = "same"')
if ! "$bin/contact_slide" "$mend" --solver flow --a 5 --R 100 --distance 0.1 --out "$work/mend" \
  >/dev/null 2>"$work/mend.err"; then
  echo "FAIL: contact_slide $mend --solver flow: a flag that mends the scene's pair was refused: $(cat "$work/mend.err")"
  failures=$((failures + 1))
fi
check $cs "--slip-solver" --model explicit --slip-solver flow
check $cs "fft.threads" "$(scene s23 <<<$'[fft]\nthreads = 0')"
check $cs "fft.planner" "$(scene s24 <<<$'[fft]\nplanner = "fast"')"
check $cs "s25.toml:2" "$(scene s25 <<<$'[contact]\na = = 3')"
check $cs "a (line 1)" "$(scene s26 <<<$'a = 3')"
check $cs "contact.a" "$(scene s27 <<<$'[contact]\na = [1, 2]')"
check $cs "--a: contact.a" --a -1
check $cs "--a: contact.a" --a nan
check $cs "--R" --R inf
check $cs "--alpha" --alpha 0
check $cs "--nu" --nu 0.7
check $cs "--protocol" --protocol fast
check $cs "--solver" --solver steepest
check $cs "--preconditioner" --preconditioner jacobi
check $cs "--preconditioner" --model explicit --slide --preconditioner interface
check $cs "--tolerance" --tolerance 0
check $cs "--threads" --threads 0
check $cs "--distance" --distance -1
check $cs "--bogus" --bogus
check $cs "scene: File does not exist" "$work/no_such_scene.toml"
check $cs "contact.R" --R 1e10
# The tip's lattice (issue 27): ranges, flags, and the explicit tip's spacing against the cutoff.
check $cs "contact.tip_angle" "$(scene t1 <<<$'[contact]\ntip_angle = 50')"
check $cs "contact.tip_mismatch" "$(scene t2 <<<$'[contact]\ntip_mismatch = -0.3')"
check $cs "--tip-angle" --tip-angle nan
check $cs "--tip-mismatch" --tip-mismatch 0.5
check $cs "tip lattice spacing" --model explicit --tip-mismatch 0.19
# Memory: the checks plan with ASPERITY_MEMORY_GIB (1 GiB here), so that the cases do not depend
# on the machine: a = 1000 d needs about 4 GiB, two contacts of 600-700 d at once about 3.6 GiB.
ASPERITY_MEMORY_GIB=1 check $cs "contact.a = 1000 d needs about" --a 1000 --R 1e6
ASPERITY_MEMORY_GIB=x check $cs "ASPERITY_MEMORY_GIB" --a 10
# Disk: the snapshots of 10 slip events and the checkpoint, planned with ASPERITY_DISK_GIB (a
# = 200 d: 10.7 MB per frame, about 0.7 GB with the path of slip 1, more than 0.1 GiB).
ASPERITY_DISK_GIB=0.1 check $cs "GiB of disk" --a 200 --R 1e4
ASPERITY_DISK_GIB=0 check $cs "ASPERITY_DISK_GIB" --a 10
# Envelopes (issue 27): tau0 is checked against the envelope that uses it.
check $cs 'contact.tau0 = 0: allowed: > 0' "$(scene e1 <<<$'[contact]\nenvelope = "adhesive"')"
check $cs 'contact.tau0 = 0.1: allowed: 0' "$(scene e2 <<<$'[contact]\ntau0 = 0.1')"
check $cs "contact.envelope" "$(scene e3 <<<$'[contact]\nenvelope = "jkr"')"
check $cs "--tau0" --envelope mixed --tau0 -1
check $cs "--envelope" --envelope jkr
check $cs 'contact.envelope = "adhesive": allowed: "hertz" with the explicit model' --model explicit --envelope adhesive --tau0 0.1
check $cs "output.path_frames" "$(scene o1 <<<$'[output]\npath_frames = -1')"
check $cs "output.precision" "$(scene o2 <<<$'[output]\nprecision = "half"')"
check $cs "output.deflate" "$(scene o3 <<<$'[output]\ndeflate = 10')"

fs=friction_sweep
check $fs "sweep.R" "$(scene w1 <<<$'[sweep]\nR = []\na = [5]')"
check $fs "contact.a: not allowed in a sweep scene" "$(scene w1a <<<$'[sweep]\nR = [535]\na = [5]\n[contact]\na = "big"')"
check $fs "--tolerance" --tolerance 0
check $fs "--tip-angle and --tip-angles" --tip-angle 1 --tip-angles 2,3
check $fs "--slip-solver" --solver lbfgs --slip-solver same
check $fs "sweep.model" "$(scene w1e <<<$'[sweep]\nR = [535]\na = [5]\nmodel = "explicit"')" --envelope mixed
check $fs "sweep.R: missing" "$(scene w0 <<<$'[sweep]\na = [5]')"
check $fs "give exactly one" "$(scene w2 <<<$'[sweep]\nR = [535]\na = [5]\na_over_bcore0 = [1]')"
check $fs "sweep.a" "$(scene w3 <<<$'[sweep]\nR = [535]\na = [-1]')"
check $fs "contact.a" "$(scene w4 <<<$'[sweep]\nR = [535]\na = [5]\n[contact]\na = 5')"
check $fs "sweep.jobs" "$(scene w5 <<<$'[sweep]\nR = [535]\na = [5]\njobs = 2000')"
check $fs "--R" --R 535,nan
check $fs "--jobs" --jobs 2000
check $fs "contact.R" --R 1e308 --a 5
ASPERITY_MEMORY_GIB=1 check $fs "GiB of memory" --R 1e6 --a 600,700 --jobs 2
ASPERITY_DISK_GIB=0.1 check $fs "GiB of disk" --R 1e4 --a 100,200 --figures
check $fs "sweep.model" "$(scene w6 <<<$'[sweep]\nR = [535]\na = [5]\nmodel = "atoms"')"
check $fs "a/R < 0.1" "$(scene w7 <<<$'[sweep]\nR = [100]\na = [5, 12]\nmodel = "both"')"
check $fs "raise R" "$(scene w8 <<<$'[sweep]\nR = [100]\na_over_bcore0 = [10]\nmodel = "explicit"')"
check $fs 'sweep.model = "both": allowed: "lfm"' "$(scene w10 <<<$'[sweep]\nR = [535]\na = [5]\nmodel = "both"\n[contact]\nenvelope = "adhesive"\ntau0 = 0.1')"
check $fs "sweep.a_over_bcore0[0] = 1000 needs a = 5000 d: allowed: [0.2, 819.2] (a in [1, 4096] d)" "$(scene w11 <<<$'[sweep]\na_over_bcore0 = [1000]\n[contact]\nenvelope = "adhesive"\ntau0 = 0.2')"
check $fs "explicit.sigma_over_d" "$(scene w9 <<<$'[sweep]\nR = [535]\na = [5]\n[explicit]\nsigma_over_d = 2')"
check $fs "sweep.tip_angle" "$(scene wt1 <<<$'[sweep]\nR = [535]\na = [5]\ntip_angle = [0, 60]')"
check $fs "sweep.tip_mismatch" "$(scene wt2 <<<$'[sweep]\nR = [535]\na = [5]\ntip_mismatch = [0.3]')"
check $fs "contact.tip_angle and sweep.tip_angle" "$(scene wt3 <<<$'[sweep]\nR = [535]\na = [5]\ntip_angle = [1, 2]\n[contact]\ntip_angle = 1')"
check $fs "tip lattice spacing" "$(scene wt4 <<<$'[sweep]\nR = [535]\na = [5]\nmodel = "explicit"\ntip_mismatch = [0.19]')"

gv=gf_validate
check $gv "hertz.a" "$(scene g1 <<<$'[hertz]\nR = 1000\na = 500')"
check $gv "hertz.radius" "$(scene g2 <<<$'[hertz]\nradius = 5')"
check $gv "--threads" --threads 0
check $gv "hertz.max_iterations" "$(scene g3 <<<$'[hertz]\nmax_iterations = 0')"
check $gv "bonded_disk.tolerance" "$(scene g4 <<<$'[bonded_disk]\ntolerance = 1')"
check $gv "hertz.tolerance = 0.5: allowed: (0, 0.01)" "$(scene g5 <<<$'[hertz]\ntolerance = 0.5')"
check $gv "--hertz-a" --hertz-a 150

pc=path_check
check $pc "--slip" --slip 0
check $pc "--max-iterations" --max-iterations -1
check $pc "--slip-solver" --solver cg --slip-solver same
check $pc "contact.a" --a 600 --R 535

# The explicit model's normal loading (contact_slide --model explicit without --slide): the
# slide's flags are refused, and a contact too large for the continuum comparison.
check $cs "--distance: not available" --model explicit --distance 2
check $cs "--alpha: not available" --model explicit --alpha 0.5
check $cs "--protocol: not available" --model explicit --protocol reference
check $cs "a/R = 0.1075" --model explicit --R 400

ap=alpha_path
check $ap "--forces" --forces 1e300
check $ap "--forces" --forces 0
check $ap "--forces" --forces nan
check $ap "--sigma-over-d" --sigma-over-d 3
check $ap "--samples" --samples 4

# fit_scaling: missing or foreign tables, a missing Regime III law, options out of range,
# damaged peierls_scan summaries (four), mixed alpha, a point given twice, a forecast without its
# pair or of an adhesive-only set. The committed tables are its inputs.
ft=fit_scaling
ref=$(cd "$(dirname "$0")/../../data/reference" && pwd)
k="--k1 2 --k2 1.8"
t="$ref/sweep_R535.csv"
fit='{"fits": {"edge": {"valid": true, "k1": 2.3, "k1_error": 0.1, "k2": 1.8, "k2_error": 0.01, '
echo "$fit"'"window_b_core": []}}}' >"$work/empty_window.json"
echo "$fit"'"window_b_core": [6, 2]}}}' >"$work/reversed_window.json"
echo '{"fits": {"edge": {"valid": true, "k1": "big"}}}' >"$work/k1_text.json"
echo "$fit"'"window_b_core": [2, 6], "k1_k2_correlation": 1.5}}}' >"$work/correlation.json"
sed 's/,535,0.7,0.5,/,536,0.6,0.5,/' "$t" >"$work/alpha06.csv"
echo "$fit"'"window_b_core": [2, 6]}}}' >"$work/law.json"

check $ft "missing.csv: no such sweep table" "$work/missing.csv" $k
check $ft "not a friction_sweep table (no column 'a')" "$ref/peierls_L128.csv" $k
check $ft "--peierls or both --k1 and --k2 are required" "$t"
check $ft "window = [5]: allowed: two values" "$t" $k --window 5
check $ft "--f-P: f_P = 0" "$t" $k --f-P 0
check $ft "fewer than 2 points in the given window" "$t" $k --window 1e3,1e4
check $ft "window_b_core = []: not a pair" "$t" --peierls "$work/empty_window.json"
check $ft "window_b_core = [6,2]: b_min must be below b_max" "$t" --peierls "$work/reversed_window.json"
check $ft "fits.edge.k1 = \"big\"" "$t" --peierls "$work/k1_text.json"
check $ft "k1_k2_correlation = 1.5: not a number in [-1, 1]" "$t" --peierls "$work/correlation.json"
check $ft "k1_k2_correlation: only with both k1 and k2" "$t" --peierls "$work/correlation.json" \
  --k1-k2-correlation 0.5
check $ft "alpha = 0.6 differs" "$t" "$work/alpha06.csv" $k
check $ft "give --k1 and --k2 together" "$t" --peierls "$work/law.json" --k1 2
check $ft "--peierls or both --k1 and --k2 are required" "$t" --k2 1.8
check $ft "give each point once" "$t" "$t" $k
check $ft "forecast_R and forecast_a: give both or neither" "$t" $k --forecast-R 800
check $ft "--forecast-a: forecast_a = [0]" "$t" $k --forecast-R 800 --forecast-a 0
check $ft "forecast_R = [800, 800]: a value is given twice" "$t" $k --forecast-R 800,800 \
  --forecast-a 300
check $ft "no table is Hertz" "$ref/adhesive_tau0p2.csv" --forecast-R 800 --forecast-a 300

echo "$((cases - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]

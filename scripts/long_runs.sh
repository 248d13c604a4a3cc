#!/usr/bin/env bash
# Starts, continues, shows and stops the long runs of the open issues, outside the repository.
# A session's end kills them (seen 2026-11-28: r800 died at 22:32:55 UTC, its checkpoint of
# 22:30 intact); a session on the machine of the last one continues them from their checkpoints
# (every 5 minutes, also inside a slip's flow); on a new machine they start again. Either way
# the command is the same:
#
#   scripts/long_runs.sh start [name...]   start or continue (default: the runs marked auto
#                                          below: this machine has 2 cores, so two at a time)
#   scripts/long_runs.sh status            where each run is: running, or stopped since when
#                                          (its log's last write), its last progress line, and
#                                          each point's latest slip (slips.csv, --largest-slip),
#                                          the pace of its last 10 slips (slips computed and d
#                                          of Dx an hour, GF a computed slip; replayed slips are
#                                          not counted), the stress the held loops' cores hold
#                                          on the axes (loop_stress_x, _y), where its figures
#                                          are (slips.png, slips_loops.png) and, for a point with
#                                          a reference table (the committed first run of r800),
#                                          whether its slips so far retrace that run's rows
#   scripts/long_runs.sh stop [name...]    checkpoint and stop (SIGUSR1, exit 3)
#   scripts/long_runs.sh peek [name...]    what each point's checkpoint holds, also inside a
#                                          slip (friction_sweep --peek), and the lines of its
#                                          states (track_loops): beside the running run
#   scripts/long_runs.sh series name...    keep the states around every slip of each point of
#                                          a running run, also of points begun later
#                                          (scripts/keep_slip_states.sh beside the run, into
#                                          <out>.series/<point>/slip_NNN_{before,after}.nc;
#                                          track_loops --front reads them whole); once asked, a
#                                          later start of the run starts its watcher again
#   scripts/long_runs.sh adopt name...     continue a stopped run with --adopt under a copy of
#                                          this checkout's build, which it keeps from then on:
#                                          a run whose binary is gone, one moved to a new build,
#                                          or one whose scene copy (<out>.scene.toml) raises a
#                                          limit its capped points stopped at (docs/reliability.md).
#                                          The run is marked (<out>.adopt): every later start
#                                          passes --adopt too, since its table keeps rows and
#                                          checkpoints of the earlier build that only --adopt
#                                          accepts (without it they would be computed again)
#
# Each run keeps its own copy of friction_sweep, named by the commit it was built from: a
# checkpoint names its build, and a later build continues it only with --adopt
# (docs/reliability.md). A run already going is left alone: friction_sweep's folder lock
# refuses a second process on the same folder anyway. Runs go at nice 10, so that builds and
# tests beside them keep the cores.
#
# Environment: RUNS (default /work/runs), BUILD_DIR (default build; built first if needed).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
runs=${RUNS:-/work/runs}
build=${BUILD_DIR:-build}

# name | scene (in data/scenes) | output folder (under $runs) | extra flags | auto (started by a
# bare `start`) | reference slips of a point (point:table in the repository, for status)
# Issue 23: Regime III at R = 800 d from a = 300 d, with step growth (data/reference/regime3_R800.md);
# R = 100 d past the crossover (data/reference/regime3_R100.md); R = 1700 d, a = 510 d
# (data/reference/regime3_R1700.md: the seed's Fig. 7(d) and Fig. 9); R = 100 d, a = 60 d with
# a 16 d cap, to a final value (data/reference/regime3_R100.md). Since 2026-11-27 r800 runs
# alone on both cores ([fft] threads = 2 in its scene, since 2026-11-28 in the repository's copy
# too, so that a new machine starts it that way), so it is the only auto run. On 2026-11-29
# (22:43 UTC) r800 was paused for r1700_a510, also on both cores: r800 needs hundreds of hours
# more, a = 510 d's first slip about 5 (data/reference/regime3_R1700.md), so r1700_a510 was
# the auto run until that slip was through (2026-11-30 06:34 UTC, finished). R = 1700 d,
# a = 360 d with the path-faithful default was the auto run after it (finished 2026-11-30
# 08:08 UTC, its row committed); since then r800 is the auto run again, the only one left.
# r800's reference is the first run's table: every run since has retraced its path (status says
# whether this one still does).
table="r800|regime3_R800_growth.toml|issue23/regime3_R800_g|--largest-slip|auto|a300_R800:data/reference/regime3_R800_a300_slips.csv
r100|regime3_R100_past_crossover.toml|r100/out|--largest-slip|
r1700_a510|regime3_R1700.toml|issue23/r1700_a510|--largest-slip --a 510|
r1700_a360|regime3_R1700.toml|issue23/r1700_a360|--largest-slip --a 360|
r100_a60|regime3_R100_a60_long.toml|r100/a60_long|--largest-slip|"

pids_of() { pgrep -f -- "--out $runs/$1( |\$)" || true; }

# A copy of this checkout's friction_sweep in $runs/bin, named by its commit (built if needed).
current_binary() {
  git diff --quiet HEAD -- core apps tracking nucleation peierls CMakeLists.txt ||
    { echo "the sources friction_sweep is built from have changes: commit first (a binary is named by its commit)" >&2; return 1; }
  local bin
  bin="$runs/bin/friction_sweep.$(git rev-parse --short HEAD)"
  if [ ! -x "$bin" ]; then
    mkdir -p "$runs/bin" || return 1
    cmake --build "$build" --target friction_sweep -j 2 >/dev/null ||
      { echo "the build of friction_sweep failed" >&2; return 1; }
    cp "$build/bin/friction_sweep" "$bin" || return 1
  fi
  echo "$bin"
}

# The run's command, in the background at nice 10, its output appended to its log.
launch() {
  local bin=$1 out=$2 scene=$3 flags=$4
  # The scene beside the run, as the run first read it (the repository's copy may move on).
  local copy="$runs/$out.scene.toml"
  [ -f "$copy" ] || cp "data/scenes/$scene" "$copy"
  # The log's progress lines carry no time of day: this line dates each start, so that the log
  # shows when every session took the run up (a session's end kills it; the log's modification
  # time is then when it stopped, which status prints).
  echo "--- $(date -u +%FT%TZ) started $(basename "$bin")${flags:+ with $flags}" >>"$runs/$out.log"
  # shellcheck disable=SC2086
  nohup nice -n 10 "$bin" "$copy" --out "$runs/$out" $flags >>"$runs/$out.log" 2>&1 &
  echo "started $(basename "$bin") (pid $!); log $runs/$out.log"
}

start() {
  local name=$1 scene=$2 out=$3 flags=$4
  if [ -n "$(pids_of "$out")" ]; then
    echo "$name: running (pid $(pids_of "$out" | tr '\n' ' '))"
    return
  fi
  mkdir -p "$runs/$out" "$runs/bin"
  # The run's binary: the one it was started with (<out>.binary), so that its checkpoint is
  # continued bit for bit; for a new run, a copy of this checkout's build.
  local bin=""
  [ -f "$runs/$out.binary" ] && bin="$runs/bin/$(cat "$runs/$out.binary")"
  if [ -z "$bin" ] || [ ! -x "$bin" ]; then
    if [ -n "$bin" ] && ls "$runs/$out"/points/*/checkpoint.cbor >/dev/null 2>&1; then
      echo "$name: its binary $bin is gone but its checkpoints are not: continue them under" \
        "this build with: scripts/long_runs.sh adopt $name" >&2
      return 1
    fi
    bin=$(current_binary) || return 1
    basename "$bin" >"$runs/$out.binary"
  fi
  # An adopted run's table and checkpoints hold rows and states of an earlier build.
  [ -f "$runs/$out.adopt" ] && flags="$flags --adopt"
  echo "$name: $(launch "$bin" "$out" "$scene" "$flags")"
  # A run whose slips are being kept keeps them across its restarts.
  # (A failure to start it does not stop the starts of the other runs named.)
  if [ -d "$runs/$out.series" ]; then
    sleep 1
    series "$name" "$scene" "$out" "$flags" || true
  fi
}

# The watcher that keeps the states around every slip of each point of a running run
# (scripts/keep_slip_states.sh over <out>, also the points that begin later), into
# <out>.series/<point>/; it follows the run's process and stops with it.
series() {
  local name=$1 out=$3
  local p
  # The run itself, not a friction_sweep --peek on its folder (which ends at once).
  p=$(for q in $(pids_of "$out"); do
    tr '\0' ' ' <"/proc/$q/cmdline" 2>/dev/null | grep -q -- '--peek' || echo "$q"
  done | head -1)
  if [ -z "$p" ]; then
    echo "$name: not running: start it first (its watcher follows the process)" >&2
    return 1
  fi
  mkdir -p "$runs/$out.series"
  # One watcher per run process: one left from an earlier process of the run (stopped, then
  # started again within its poll) ends by itself and is not this one.
  if pgrep -f -- "keep_slip_states.sh $runs/$out $runs/$out.series $p( |\$)" >/dev/null; then
    echo "$name: its slips' states are being kept in $runs/$out.series"
    return 0
  fi
  nohup bash scripts/keep_slip_states.sh "$runs/$out" "$runs/$out.series" "$p" \
    >>"$runs/$out.series/watch.log" 2>&1 &
  echo "$name: keeping its slips' states in $runs/$out.series/<point> (watcher pid $!)"
}

adopt() {
  local name=$1 scene=$2 out=$3 flags=$4
  if [ -n "$(pids_of "$out")" ]; then
    echo "$name: running: stop it first (scripts/long_runs.sh stop $name)" >&2
    return 1
  fi
  mkdir -p "$runs/$out"
  local bin
  bin=$(current_binary) || return 1
  basename "$bin" >"$runs/$out.binary"
  date -u +%FT%TZ >"$runs/$out.adopt"
  echo "$name: $(launch "$bin" "$out" "$scene" "$flags --adopt")"
}

# Whether a point's slips so far are those of a reference table (a committed earlier run of the
# same point): every column both tables have, as text, but the cost columns (gf_applications,
# wall_s: another machine's) and cells the reference leaves empty. Prints one line.
compare_slips() {
  local table=$1 reference=$2
  awk -F, -v ref="$(basename "$reference")" '
    FNR == 1 {
      for (i = 1; i <= NF; ++i) {
        if (FILENAME == ARGV[1]) rcol[$i] = i
        else col[$i] = i
      }
      next
    }
    FILENAME == ARGV[1] { rrow[FNR - 1] = $0; m = FNR - 1; next }
    { row[FNR - 1] = $0; n = FNR - 1 }
    END {
      shared = 0
      for (c in col) if ((c in rcol) && c != "gf_applications" && c != "wall_s") names[++shared] = c
      k = n < m ? n : m
      for (s = 1; s <= k; ++s) {
        split(row[s], a, ","); split(rrow[s], b, ",")
        for (j = 1; j <= shared; ++j) {
          c = names[j]; x = a[col[c]]; y = b[rcol[c]]
          if (y != "" && x "" != y "") {  # as text: mawk compares numeric-looking fields as numbers
            printf "    against %s: slip %d differs in %s (%s, the reference %s)\n", ref, s, c, x, y
            exit
          }
        }
      }
      if (k == 0) exit
      printf "    against %s: slips 1-%d equal its rows in the %d columns both have", ref, k, shared
      if (n > m) printf "; slips %d-%d are past its %d rows", m + 1, n, m
      printf "\n"
    }' "$reference" "$table"
}

status() {
  local name=$1 out=$3 reference=${5:-}
  local state="stopped"
  # A stopped run's log was last written when it stopped (or was killed, as at a session's end).
  [ -f "$runs/$out.log" ] && state="stopped since $(date -u -r "$runs/$out.log" +%FT%TZ)"
  [ -n "$(pids_of "$out")" ] && state="running"
  local last="(no log)"
  [ -f "$runs/$out.log" ] && last=$(grep -v '^ *$' "$runs/$out.log" | grep -v '^--- ' | tail -1 | cut -c1-240)
  echo "$name [$state, $(cat "$runs/$out.binary" 2>/dev/null || echo 'no binary')]: $last"
  # Each point's latest slip from its slips.csv (--largest-slip): what the slide has found so far
  # (the loops it holds), read by column name.
  local table
  for table in "$runs/$out"/points/*/largest_slip/slips.csv; do
    [ -f "$table" ] || continue
    awk -F, -v point="$(basename "$(dirname "$(dirname "$table")")")" '
      NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
      {
        last = $0; n = NR - 1
        dx[n] = $col["Dx"]
        if ("wall_s" in col) { wall[n] = $col["wall_s"]; gf[n] = $col["gf_applications"] }
        # A replayed slip (replay_of not 0: the slip it repeats, or -1 where an earlier build did
        # not say) repeats an earlier cycle at no cost: counted in the pace as a slip, it would
        # make a point that replays look fast (docs/tracking.md).
        replayed[n] = ("replay_of" in col && $col["replay_of"] + 0 != 0)
      }
      END {
        if (n == 0) { printf "  %s: no slip yet\n", point; exit }
        split(last, f, ",")
        printf "  %s: %d slips; last: slip %s at Dx = %.5g d, Fx %.6g -> %.6g, %s sites, %s loops (area %.6g d^2), slipped area %.6g d^2", point, n, f[col["slip"]], f[col["Dx"]], f[col["Fx_before"]], f[col["Fx_after"]], f[col["slipped_sites"]], f[col["loops"]], f[col["loop_area"]], f[col["slipped_area"]]
        if ("gf_applications" in col && f[col["gf_applications"]] != "")
          printf ", at %s GF, %.2f h", f[col["gf_applications"]], f[col["wall_s"]] / 3600
        printf "\n"
        # What the cores of the held loops hold on the axes through the tip centre (tracking.md),
        # against tau_max there: compare with the local Peierls stress of a scan.
        if ("loop_stress_x" in col) {
          s = ""
          for (a = 1; a <= 2; ++a) {
            ax = a == 1 ? "x" : "y"
            v = f[col["loop_stress_" ax]]; t = f[col["loop_tau_max_" ax]]
            if (v != "" && v != "nan")
              s = s sprintf("%s%s: %.4g G at tau_max %.4g G", s == "" ? "" : ", ", ax, v, t)
          }
          if (s != "") printf "    held loop cores (%s)\n", s
        }
        # The pace of the last slips (up to 10 cycles, from their cost columns): what planning a
        # run of days needs. Across a restart the wall time holds the set-up (docs/tracking.md).
        k = n - 1 < 10 ? n - 1 : 10
        if (k >= 1 && wall[n] != "" && wall[n - k] != "" && wall[n] > wall[n - k]) {
          h = (wall[n] - wall[n - k]) / 3600
          r = 0
          for (i = n - k + 1; i <= n; ++i) r += replayed[i]
          c = k - r
          printf "    pace over slips %d-%d: %.3g slips/h, %.3g d of Dx/h", n - k + 1, n, c / h, (dx[n] - dx[n - k]) / h
          if (r > 0) printf " (%d replayed slips left out of the count; their Dx is in)", r
          if (c > 0 && gf[n] != "" && gf[n - k] != "") printf ", %.0f GF a slip", (gf[n] - gf[n - k]) / c
          printf "\n"
        }
      }' "$table"
    # Its figures (friction and loops at every slip), those the run's build has drawn.
    local fig figs=""
    for fig in slips.png slips_loops.png; do
      [ -f "$(dirname "$table")/$fig" ] && figs="$figs${figs:+, }$(dirname "$table")/$fig"
    done
    [ -n "$figs" ] && echo "    figures: $figs"
    local point
    point=$(basename "$(dirname "$(dirname "$table")")")
    if [ -n "$reference" ] && [ "${reference%%:*}" = "$point" ] && [ -f "${reference#*:}" ]; then
      compare_slips "$table" "${reference#*:}"
    fi
    # The states kept around each slip (series), if asked for.
    local kept="$runs/$out.series/$(basename "$(dirname "$(dirname "$table")")")"
    if [ -d "$kept" ]; then
      local pairs missed=0 watching="no watcher"
      pairs=$(find "$kept" -maxdepth 1 -name 'slip_*_after.nc' | wc -l)
      [ -f "$kept/missed.txt" ] && missed=$(wc -l <"$kept/missed.txt")
      if pgrep -f -- "keep_slip_states.sh $runs/$out $runs/$out.series " >/dev/null; then
        watching="watcher running"
      fi
      echo "    series: $pairs slips' states kept, $missed missed ($watching): $kept"
    fi
  done
  return 0
}

# What each point's checkpoint holds, beside the running run or after it stopped: friction_sweep
# --peek (this checkout's build: it reads the checkpoint of any build) writes the last accepted
# state, the peak and, inside a slip, where the slip's flow stands into points/<p>/peek/, and
# track_loops finds the lines of the accepted and the flow's state (points/<p>/peek/<state>_lines/).
# A slip through a = 510 d flows for hours before the run writes its states.
peek() {
  local name=$1 out=$3 flags=$4
  local copy="$runs/$out.scene.toml"
  if [ ! -f "$copy" ] || [ ! -d "$runs/$out/points" ]; then
    echo "$name: nothing to look at (no $copy or $runs/$out/points)"
    return
  fi
  if [ ! -x "$build/bin/friction_sweep" ] || [ ! -x "$build/bin/track_loops" ]; then
    echo "$name: build friction_sweep and track_loops first ($build/bin)" >&2
    return 1
  fi
  # shellcheck disable=SC2086
  "$build/bin/friction_sweep" "$copy" --out "$runs/$out" $flags --peek || return 1
  local nc
  for nc in "$runs/$out"/points/*/peek/accepted.nc "$runs/$out"/points/*/peek/flow.nc; do
    [ -f "$nc" ] || continue
    local into="${nc%.nc}_lines"
    "$build/bin/track_loops" "$nc" --out "$into" >"$into.log" 2>&1 ||
      { echo "  track_loops failed on $nc: $into.log" >&2; continue; }
    python3 - "$into/lines.json" <<'PY'
import json, sys
frame = json.load(open(sys.argv[1]))["frames"][0]
lines = frame["lines"]
loops = [l for l in lines if l["kind"] == "loop"]
print(f"  {frame['label']} (Dx = {frame['Dx']:.4f} d): {len(loops)} loop(s), "
      f"{len(lines) - len(loops)} other line(s); " + "; ".join(
          f"{l['kind']} {l['length']:.1f} d, screw {100 * l['screw_fraction']:.0f} %, "
          f"{l['x_extent']:.0f} x {l['y_extent']:.0f} d" for l in lines[:8]))
print(f"    {sys.argv[1].rsplit('/', 1)[0]}/frame_0000.png")
PY
  done
}

stop() {
  local name=$1 out=$3
  local p
  p=$(pids_of "$out")
  if [ -z "$p" ]; then
    echo "$name: not running"
    return
  fi
  kill -USR1 $p
  echo "$name: asked to checkpoint and stop (pid $p)"
}

action=${1:-status}
shift || true
want=" $* "
while IFS='|' read -r name scene out flags auto reference; do
  if [ "$want" != "  " ]; then
    [[ "$want" == *" $name "* ]] || continue
  elif [ "$action" = start ] && [ "$auto" != auto ]; then
    continue
  fi
  case $action in
    start) start "$name" "$scene" "$out" "$flags" ;;
    status) status "$name" "$scene" "$out" "$flags" "$reference" ;;
    stop) stop "$name" "$scene" "$out" "$flags" ;;
    peek) peek "$name" "$scene" "$out" "$flags" ;;
    series)
      [ "$want" != "  " ] || { echo "series: name the runs" >&2; exit 2; }
      series "$name" "$scene" "$out" "$flags"
      ;;
    adopt)
      [ "$want" != "  " ] || { echo "adopt: name the runs" >&2; exit 2; }
      adopt "$name" "$scene" "$out" "$flags"
      ;;
    *)
      echo "usage: scripts/long_runs.sh start|status|stop|adopt|peek|series [name...]" >&2
      exit 2
      ;;
  esac
done <<<"$table"

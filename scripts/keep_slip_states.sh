#!/usr/bin/env bash
# Keeps the states around every slip of a running sweep point, beside the run: a series that
# track_loops --profiles --front reads whole (the stress the held loop's front holds, slip by
# slip, and where each slip moved it: data/reference/regime3_R800.md, "The whole front").
#
# friction_sweep --largest-slip keeps only the largest slip's pair and the latest slip's
# (latest_slip_before.nc, latest_slip_after.nc, replaced at every slip), so that a run's disk
# does not grow with its slips; this watcher, outside the run, copies the latest pair each time
# slips.csv gains a row, into SERIES/slip_NNN_before.nc and slip_NNN_after.nc. A pair is kept
# only if both files carry the labels of that row's slip (slip_NNN_before, slip_NNN_after): a
# copy is of one whole file (the run replaces them by renaming), and a slip that came before the
# watcher copied the last one's pair is named in SERIES/missed.txt instead (at a = 300 d a slip
# takes minutes, the poll a few seconds). Slips already kept are left alone, so the watcher can
# be stopped and started again with its run (scripts/long_runs.sh series).
#
# Usage: scripts/keep_slip_states.sh POINT_DIR SERIES_DIR [PID [POLL_S]]
#   POINT_DIR  a sweep point's folder (<out>/points/<point>), whose largest_slip/ it reads
#   PID        stop once this process has ended (after a last look); default: run until killed
#   POLL_S     seconds between looks at slips.csv (default 5)
set -euo pipefail
point=${1:?usage: keep_slip_states.sh POINT_DIR SERIES_DIR [PID [POLL_S]]}
series=${2:?usage: keep_slip_states.sh POINT_DIR SERIES_DIR [PID [POLL_S]]}
pid=${3:-}
poll=${4:-5}
dir="$point/largest_slip"
mkdir -p "$series"
command -v ncdump >/dev/null || { echo "keep_slip_states: needs ncdump (netcdf-bin)" >&2; exit 1; }

# The snapshot label of a file's first frame (its global attribute), or empty.
label_of() { ncdump -h "$1" 2>/dev/null | sed -n 's/^[[:space:]]*:label = "\(.*\)" ;$/\1/p' | head -1; }

# Rows of slips.csv (slips so far), 0 before the first.
rows() { [ -f "$dir/slips.csv" ] && echo $(($(wc -l <"$dir/slips.csv") - 1)) || echo 0; }

# The highest slip kept or named missed so far: where a restarted watcher goes on.
done_upto() {
  local n=0 f k
  for f in "$series"/slip_*_after.nc; do
    [ -f "$f" ] || continue
    k=$(basename "$f" _after.nc)
    k=$((10#${k#slip_}))
    [ "$k" -gt "$n" ] && n=$k
  done
  if [ -f "$series/missed.txt" ]; then
    while read -r k _; do [ "$k" -gt "$n" ] && n=$k; done <"$series/missed.txt"
  fi
  echo "$n"
}

look() {
  local n last k name tmp ok
  n=$(rows)
  last=$(done_upto)
  [ "$n" -gt "$last" ] || return 0
  # Every slip between the last one handled and the newest came and went unseen.
  for ((k = last + 1; k < n; ++k)); do
    echo "$k its states were replaced before they were copied" >>"$series/missed.txt"
  done
  name=$(printf 'slip_%03d' "$n")
  tmp=$(mktemp -d "$series/.copy.XXXXXX")
  ok=1
  cp "$dir/latest_slip_before.nc" "$tmp/before.nc" 2>/dev/null || ok=0
  cp "$dir/latest_slip_after.nc" "$tmp/after.nc" 2>/dev/null || ok=0
  if [ "$ok" = 1 ] && [ "$(label_of "$tmp/before.nc")" = "${name}_before" ] &&
    [ "$(label_of "$tmp/after.nc")" = "${name}_after" ]; then
    mv "$tmp/before.nc" "$series/${name}_before.nc"
    mv "$tmp/after.nc" "$series/${name}_after.nc"
    echo "kept $name ($(date -u +%FT%TZ))"
  elif [ "$(rows)" -gt "$n" ]; then
    # A newer slip replaced the pair while it was copied: this one is missed, the newer one is
    # taken at the next look.
    echo "$n its states were replaced while they were copied" >>"$series/missed.txt"
  fi
  # Else the row came before its files (the run writes the pair, then the table): next look.
  rm -rf "$tmp"
}

while :; do
  look
  if [ -n "$pid" ] && ! kill -0 "$pid" 2>/dev/null; then
    look  # what the run wrote as it stopped
    exit 0
  fi
  sleep "$poll"
done

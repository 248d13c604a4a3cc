#!/usr/bin/env bash
# Keeps the states around every slip of a running sweep, beside the run: a series that
# track_loops --profiles --front reads whole (the stress the held loop's front holds, slip by
# slip, and where each slip moved it: data/reference/regime3_R800.md, "The whole front").
#
# friction_sweep --largest-slip keeps only the largest slip's pair and the latest slip's
# (latest_slip_before.nc, latest_slip_after.nc, replaced at every slip, then slips.csv), so
# that a run's disk does not grow with its slips; this watcher, outside the run, copies the
# latest pair each time slips.csv gains a slip, into SERIES/<point>/slip_NNN_before.nc and
# slip_NNN_after.nc. The slip is the number in the table's last row (its `slip` column, not
# the count of rows: a resumed run may restart its table). A pair is kept only if both files
# carry that slip's labels (slip_NNN_before, slip_NNN_after): a copy is of one whole file (the
# run replaces them by renaming), and a slip whose pair was replaced before the watcher copied
# it is named once in SERIES/<point>/missed.txt instead (at a = 300 d a slip takes minutes,
# the poll a few seconds). Slips already kept are left alone, so the watcher can be stopped and
# started again with its run (scripts/long_runs.sh series). It stops keeping when the disk has
# less than MIN_FREE_GB (default 5) free, and says so.
#
# Usage: scripts/keep_slip_states.sh OUT SERIES [PID [POLL_S]]
#   OUT     a friction_sweep output folder (every point in OUT/points/, also those that begin
#           later) or one point's folder (OUT/largest_slip/)
#   SERIES  where the pairs go (SERIES/<point>/ for each point)
#   PID     stop once this process has ended (after a last look); default: run until killed
#   POLL_S  seconds between looks (default 5)
set -euo pipefail
out=${1:?usage: keep_slip_states.sh OUT SERIES [PID [POLL_S]]}
series=${2:?usage: keep_slip_states.sh OUT SERIES [PID [POLL_S]]}
pid=${3:-}
poll=${4:-5}
min_free_gb=${MIN_FREE_GB:-5}
command -v ncdump >/dev/null || { echo "keep_slip_states: needs ncdump (netcdf-bin)" >&2; exit 1; }

# The snapshot label of a file's first frame (its global attribute), or empty.
label_of() { ncdump -h "$1" 2>/dev/null | sed -n 's/^[[:space:]]*:label = "\(.*\)" ;$/\1/p' | head -1; }

# The slip of the last row of a slips.csv (its `slip` column), 0 without rows.
last_slip() {
  [ -f "$1" ] || { echo 0; return; }
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "slip") c = i; next }
           c && $c != "" { v = $c } END { print v + 0 }' "$1"
}

# The highest slip kept or named missed in a point's series: where a restarted watcher goes on.
done_upto() {
  local kept=$1 n=0 f k
  for f in "$kept"/slip_*_after.nc; do
    [ -f "$f" ] || continue
    k=$(basename "$f" _after.nc)
    k=$((10#${k#slip_}))
    if [ "$k" -gt "$n" ]; then n=$k; fi
  done
  if [ -f "$kept/missed.txt" ]; then
    while read -r k _; do
      if [ "$k" -gt "$n" ]; then n=$k; fi
    done <"$kept/missed.txt"
  fi
  echo "$n"
}

# A point's series as a watcher killed mid-copy may have left it: no temporary copies, no
# "before" without its "after".
tidy() {
  local kept=$1 f
  rm -rf "$kept"/.copy.*
  for f in "$kept"/slip_*_before.nc; do
    [ -f "$f" ] || continue
    [ -f "${f%_before.nc}_after.nc" ] || rm -f "$f"
  done
}

full=0
look() {
  local point=$1 kept=$2 dir n last k name tmp ok
  dir="$point/largest_slip"
  n=$(last_slip "$dir/slips.csv")
  last=$(done_upto "$kept")
  [ "$n" -gt "$last" ] || return 0
  if [ "$(df -Pk "$kept" | awk 'NR == 2 { print int($4 / 1048576) }')" -lt "$min_free_gb" ]; then
    [ "$full" = 1 ] || echo "less than $min_free_gb GB free on the disk of $kept: not keeping slips from $n on"
    full=1
    return 0
  fi
  full=0
  # Every slip between the last one handled and the newest came and went unseen.
  for ((k = last + 1; k < n; ++k)); do
    echo "$k its states were replaced before they were copied" >>"$kept/missed.txt"
  done
  name=$(printf 'slip_%03d' "$n")
  tmp=$(mktemp -d "$kept/.copy.XXXXXX")
  ok=1
  cp "$dir/latest_slip_before.nc" "$tmp/before.nc" 2>/dev/null || ok=0
  cp "$dir/latest_slip_after.nc" "$tmp/after.nc" 2>/dev/null || ok=0
  if [ "$ok" = 1 ] && [ "$(label_of "$tmp/before.nc")" = "${name}_before" ] &&
    [ "$(label_of "$tmp/after.nc")" = "${name}_after" ]; then
    mv "$tmp/before.nc" "$kept/${name}_before.nc"
    mv "$tmp/after.nc" "$kept/${name}_after.nc"
    echo "$(basename "$point"): kept $name ($(date -u +%FT%TZ))"
  elif [ "$(last_slip "$dir/slips.csv")" -gt "$n" ]; then
    # A newer slip replaced the pair while it was copied: this one is missed, the newer one is
    # taken at the next look.
    echo "$n its states were replaced while they were copied" >>"$kept/missed.txt"
  fi
  # Else the files are not yet the row's (the run writes the pair, then the table): next look.
  rm -rf "$tmp"
}

# The points to watch: OUT itself if it is a point, else every point folder under OUT/points.
points() {
  if [ -d "$out/largest_slip" ] || [ ! -d "$out/points" ]; then
    echo "$out"
  else
    local p
    for p in "$out"/points/*/; do
      [ -d "$p" ] && echo "${p%/}"
    done
  fi
  return 0
}

look_all() {
  local point kept
  while read -r point; do
    [ -n "$point" ] || continue
    kept="$series/$(basename "$point")"
    if [ ! -d "$kept" ]; then
      mkdir -p "$kept"
    fi
    look "$point" "$kept"
  done < <(points)
}

mkdir -p "$series"
for kept in "$series"/*/; do
  [ -d "$kept" ] && tidy "${kept%/}"
done
while :; do
  look_all
  if [ -n "$pid" ] && ! kill -0 "$pid" 2>/dev/null; then
    look_all  # what the run wrote as it stopped
    exit 0
  fi
  sleep "$poll"
done

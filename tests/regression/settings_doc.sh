#!/usr/bin/env bash
# A doc lists a tool's settings as the tool's --list-settings prints them: the doc is made from
# the one description of each setting and must not drift from it. The tool's rows sit between
# "<!-- settings: TOOL ... -->" and "<!-- end of settings -->"; a doc without such markers is
# one table, the tool's: every table row of the doc.
# With BASE_TOOL, the tool's scene is BASE_TOOL's without KEYs plus the rows of the doc's
# section (friction_sweep: contact_slide's scene without contact.a and contact.R, and the
# [sweep] and [explicit] tables): the doc keeps only the rows the tool adds.
# Usage: settings_doc.sh TOOL DOC [BASE_TOOL KEY...]
set -euo pipefail
tool=$1
doc=$2
shift 2
name=$(basename "$tool")
if grep -q "^<!-- settings: $name " "$doc"; then
  rows=$(awk -v start="<!-- settings: $name " \
    'index($0, start) == 1 {inside=1; next} /^<!-- end of settings -->/{inside=0} inside && /^\|/' "$doc")
elif grep -q '^<!-- settings: ' "$doc"; then
  echo "$doc: no section <!-- settings: $name ... -->"
  exit 1
else
  rows=$(grep '^|' "$doc" || true)
fi
[ -n "$rows" ] || { echo "$doc: no settings table found"; exit 1; }
expected=$rows
if [ $# -gt 0 ]; then
  base=$1
  shift
  skip='^$'
  for key in "$@"; do skip="$skip|^\\| \`$key\` \\|"; done
  # The base's header and rows but the skipped keys, then the section's rows without its header.
  expected=$(
    "$base" --list-settings | grep -Ev "$skip"
    printf '%s\n' "$rows" | tail -n +3
  )
fi
diff <("$tool" --list-settings) <(printf '%s\n' "$expected") || {
  echo "$doc differs from $name --list-settings: regenerate its table"
  exit 1
}

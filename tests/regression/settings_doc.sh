#!/usr/bin/env bash
# A doc lists a tool's settings as the tool's --list-settings prints them: the doc is made from
# the one description of each setting and must not drift from it. docs/settings.md is
# contact_slide's table alone (every table row of the doc); a doc with other tables too
# (docs/tracking.md) marks the tool's between "<!-- settings: ... -->" and
# "<!-- end of settings -->".
# Usage: settings_doc.sh TOOL DOC
set -euo pipefail
tool=$1
doc=$2
if grep -q '^<!-- settings: ' "$doc"; then
  rows=$(awk '/^<!-- settings: /{inside=1; next} /^<!-- end of settings -->/{inside=0} inside && /^\|/' "$doc")
else
  rows=$(grep '^|' "$doc" || true)
fi
[ -n "$rows" ] || { echo "$doc: no settings table found"; exit 1; }
diff <("$tool" --list-settings) <(printf '%s\n' "$rows") || {
  echo "$doc differs from $(basename "$tool") --list-settings: regenerate its table"
  exit 1
}

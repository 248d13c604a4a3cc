#!/usr/bin/env bash
# docs/settings.md lists the settings as contact_slide --list-settings prints them: the doc is
# made from the one description of each setting and must not drift from it.
# Usage: settings_doc.sh CONTACT_SLIDE DOC
set -euo pipefail
diff <("$1" --list-settings) <(grep '^|' "$2") || {
  echo "docs/settings.md differs from contact_slide --list-settings: regenerate its table"
  exit 1
}

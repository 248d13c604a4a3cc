#!/usr/bin/env bash
# Style tier: every C++ file of the repository is as clang-format leaves it (the repository's
# .clang-format; the developers' guide asks for clang-format on all our code).
# Usage: clang_format.sh <clang-format> <source dir>
# The files are the ones git tracks (a clean clone's), or, outside a git checkout, every .cpp,
# .hpp and .h under the source tree but build folders. clang-format's output depends on its
# major version: the repository is formatted with Debian 12's, 14; another major version skips
# the test (exit 77) rather than report its own opinions as our violations.
set -euo pipefail
clang_format=$1
cd "$2"
version=$("$clang_format" --version | sed -n 's/.*version \([0-9][0-9]*\)\..*/\1/p')
if [ "$version" != 14 ]; then
  echo "clang-format major version ${version:-unknown}, not 14: skipped"
  exit 77
fi
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -d '' files < <(git ls-files -z -- '*.cpp' '*.hpp' '*.h')
else
  mapfile -d '' files < <(find . -path './build*' -prune -o \
    \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -type f -print0)
fi
[ ${#files[@]} -gt 0 ] || { echo "no C++ files found under $2"; exit 1; }
if ! "$clang_format" --dry-run -Werror "${files[@]}"; then
  echo "not clang-formatted (above); fix with: $clang_format -i <file>"
  exit 1
fi
echo "${#files[@]} files as clang-format $version leaves them"

#!/usr/bin/env bash
# Every C++ file of the project is formatted as .clang-format says (Debian 12's clang-format 14,
# installed by ./dynpm.sh deps). Prints each file that differs with the first lines of the
# difference; exit 1 if any. Fix with: clang-format -i FILE
set -euo pipefail
cd "${1:-.}"
command -v clang-format >/dev/null || { echo "clang-format is not installed (./dynpm.sh deps)"; exit 1; }
mapfile -t files < <(find src include cli tests bench fuzz viewer/embed \
  \( -name '*.cpp' -o -name '*.h' \) -not -path '*/node_modules/*' | sort)
# One clang-format for every file: a process a file took 20 times as long (each loads clang).
# Only when one differs are they looked at one by one, to show where.
if clang-format --dry-run --Werror "${files[@]}" >/dev/null 2>&1; then
  echo "all ${#files[@]} C++ files formatted ($(clang-format --version))"
  exit 0
fi
bad=0
for f in "${files[@]}"; do
  if ! clang-format --dry-run --Werror "$f" >/dev/null 2>&1; then
    echo "$f: not formatted as .clang-format says; the difference:"
    clang-format "$f" | diff "$f" - | head -12 || true
    bad=$((bad + 1))
  fi
done
if [ "$bad" -gt 0 ]; then
  echo "$bad of ${#files[@]} C++ files differ from .clang-format (fix: clang-format -i FILE)"
  exit 1
fi
echo "all ${#files[@]} C++ files formatted ($(clang-format --version))"

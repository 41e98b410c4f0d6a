#!/bin/sh
# Every tracked C and C++ file is formatted as .clang-format says. Pinned to clang-format 14
# (Debian 12's, which ./run installs): other major versions format some constructs differently,
# so with one of them, or outside a git checkout, the check reports itself skipped (exit 77).
set -eu
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null 2>&1 || { echo "format_check: no clang-format: skipped"; exit 77; }
version=$(clang-format --version)
case "$version" in
  *"version 14."*) ;;
  *) echo "format_check: $version is not clang-format 14: skipped"; exit 77 ;;
esac
git rev-parse --git-dir >/dev/null 2>&1 || { echo "format_check: not a git checkout: skipped"; exit 77; }
list=$(mktemp)
trap 'rm -f "$list" "$list.out"' EXIT
git ls-files '*.cc' '*.h' '*.c' > "$list"
xargs clang-format --dry-run < "$list" > "$list.out" 2>&1 || true
if grep -q "warning:" "$list.out"; then
  grep "warning:" "$list.out" | head -20
  echo "format_check: $(grep "warning:" "$list.out" | cut -d: -f1 | sort -u | wc -l) file(s) need clang-format -i"
  exit 1
fi
echo "format_check: $(wc -l < "$list") files formatted as .clang-format says"

#!/usr/bin/env bash
# Regenerates the expected outputs of golden cases (tests/golden/<case>/expected/) from the current
# build, after an intentional change of behaviour. README "Golden files" says when that is
# legitimate; review the diff (git diff --stat tests/golden) and say why in the commit message.
#
# Usage: tests/golden/regenerate.sh [-B BUILD_DIR] [CASE...]
#   BUILD_DIR  a configured build folder (default: build/ at the project root)
#   CASE       case folder names (default: every case); cases whose shared data is absent are
#              skipped and keep their expected files
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build="$root/build"
if [ "${1:-}" = "-B" ]; then
  build=$(cd "$2" && pwd)
  shift 2
fi
cmake --build "$build" --target golden_test retarget -j2
filter='Cases/Golden.Matches/*'
if [ $# -gt 0 ]; then
  filter=''
  for c in "$@"; do
    [ -f "$root/tests/golden/$c/case.yaml" ] || { echo "no such golden case: $c" >&2; exit 2; }
    filter="$filter${filter:+:}Cases/Golden.Matches/$c"
  done
fi
RT_GOLDEN_REGENERATE=1 RT_TEST_TMPDIR="$build/tests/golden/tmp" \
  "$build/tests/golden/golden_test" --gtest_filter="$filter"
echo
echo "Now check that the golden tests pass and review what changed:"
echo "  ctest --test-dir $build -R Golden --output-on-failure"
echo "  git -C $root diff --stat tests/golden"

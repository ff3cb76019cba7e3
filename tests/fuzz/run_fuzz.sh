#!/bin/sh
# ctest wrapper for one fuzz target of the sanitizer build (tests/CMakeLists.txt):
#   run_fuzz.sh DRIVER TARGET SECONDS SHARED_DATA_DIR ARTIFACT_DIR
# Exit 77 (skip) when DRIVER was not built (.ci/setup builds it under build/fuzz-asan); otherwise
# the driver's status: 0, or 1 on a failure, with the failing input saved under ARTIFACT_DIR.
driver=$1 target=$2 seconds=$3 shared=$4 artifacts=$5
if [ ! -x "$driver" ]; then
  echo "skip: $driver is not built; .ci/setup builds the ASan/UBSan fuzz drivers (README 'Tests, sanitizers, fuzzing')"
  exit 77
fi
mkdir -p "$artifacts"
# The driver bounds itself (--seconds, a per-input timeout); this outer limit only catches a
# driver that cannot stop (a hang outside an input).
timeout -k 5 $((seconds + 120)) "$driver" "$target" --seconds "$seconds" --shared "$shared" --artifacts "$artifacts"
rc=$?
if [ "$rc" -ne 0 ]; then
  input="$artifacts/fuzz-$target-failure.input"
  [ "$rc" -eq 124 ] && echo "run_fuzz.sh: the driver did not stop within $((seconds + 120)) s"
  if [ -f "$input" ]; then
    echo "run_fuzz.sh: replay with: $driver $target $input   (first bytes below)"
    head -c 512 "$input" | od -A d -c | head -20
  fi
  exit 1
fi

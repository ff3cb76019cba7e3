#!/bin/sh
# check_target_list.sh DRIVER "TARGET ...": the driver's targets (rt_fuzz --list) are exactly the
# ones ctest runs (RT_FUZZ_TARGETS in tests/CMakeLists.txt). Exit 77 (skip) when not built.
driver=$1 listed=$2
[ -x "$driver" ] || { echo "skip: $driver is not built (.ci/setup builds it)"; exit 77; }
have=$("$driver" --list | sort | tr '\n' ' ')
want=$(printf '%s\n' $listed | sort | tr '\n' ' ')
[ "$have" = "$want" ] && exit 0
echo "rt_fuzz --list: $have"
echo "RT_FUZZ_TARGETS: $want"
exit 1

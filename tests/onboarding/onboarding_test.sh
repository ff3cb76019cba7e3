#!/usr/bin/env bash
# Issue 17 acceptance on robots written the unconventional way (make_unconventional_urdf.py: root
# facing backwards, DH-style link frames, Y_UP millimetre COLLADA meshes behind package:///,
# mirrored meshes, optionally many finger joints), made from the shared G1 and H1 URDFs. With no
# hand edit, `init-robot` must write a config that `inspect` accepts, that finds the facing, that
# converts a real walk within the joint limits with a landmark error median within 20 % of the
# config guessed for the unmodified URDF, and whose standing clip passes the check; the foot lift
# and slow steps pass where the robot can stand on one foot (G1) and fail where it cannot (H1).
#
#   onboarding_test.sh RETARGET SOURCE_DIR SHARED_DATA_DIR WORK_DIR
# Exit 77 (skip) without the shared data or python3 with numpy.
set -u
retarget=$1 src=$2 data=$3 work=$4
[ -d "$data/robots" ] && [ -f "$data/bvh/cmu_max_131_01_start_walk_stop.bvh" ] || { echo "skip: no shared data at $data"; exit 77; }
py=""
for candidate in /usr/bin/python3 python3; do
  "$candidate" -c "import numpy" 2>/dev/null && { py=$candidate; break; }
done
[ -n "$py" ] || { echo "skip: python3 with numpy is missing"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
status=0
fail() { echo "FAIL: $*"; status=1; }
median() { grep -o "error median [0-9.]*" "$1" | awk '{print $3}'; }

# robot NAME URDF PACKAGE_ROOT FINGERS STANDS_ON_ONE_FOOT(yes|no)
robot() {
  local name=$1 urdf=$2 root=$3 fingers=$4 one_foot=$5 dir="$work/$1"
  echo "== $name"
  "$py" "$src/tests/onboarding/make_unconventional_urdf.py" "$urdf" "$dir" "${name}_description" \
    --package-root "$root" --fingers "$fingers" || { fail "$name: generator"; return; }
  local odd
  odd=$(ls "$dir/${name}_description/"*_unconventional.urdf)
  "$retarget" init-robot "$odd" -o "$dir/guessed" > "$dir/init.log" 2>&1 || { cat "$dir/init.log"; fail "$name: init-robot"; return; }
  "$retarget" init-robot "$urdf" --package-path "$root" -o "$dir/plain" > "$dir/init_plain.log" 2>&1 || { fail "$name: init-robot (plain)"; return; }
  grep -q "forward = root -x, up = root z" "$dir/init.log" || fail "$name: facing not found: $(grep 'root ' "$dir/init.log")"
  "$retarget" inspect "$dir/guessed" > "$dir/inspect.log" 2>&1 || { tail -5 "$dir/inspect.log"; fail "$name: inspect"; }

  local walk="$data/bvh/cmu_max_131_01_start_walk_stop.bvh"
  "$retarget" convert "$walk" --robot "$dir/guessed" -o "$dir/walk.csv" > "$dir/walk.log" 2>&1 || fail "$name: convert walk"
  "$retarget" convert "$walk" --robot "$dir/plain" -o "$dir/walk_plain.csv" > "$dir/walk_plain.log" 2>&1 || fail "$name: convert walk (plain)"
  local m m0
  m=$(median "$dir/walk.log") m0=$(median "$dir/walk_plain.log")
  echo "$name: walk landmark error median $m m (unmodified URDF: $m0 m)"
  awk -v m="$m" -v m0="$m0" 'BEGIN { exit !(m != "" && m0 != "" && m <= 1.2 * m0) }' || fail "$name: landmark median $m m vs $m0 m"
  grep -q "limits      0 position violations" "$dir/walk.log" || fail "$name: walk outside the joint limits: $(grep 'limits  ' "$dir/walk.log")"

  for clip in stand foot_lift slow_steps; do
    "$retarget" convert "$src/examples/clips/$clip.bvh" --robot "$dir/guessed" -o "$dir/$clip.csv" --check > "$dir/$clip.log" 2>&1
    local verdict expected=PASSED
    verdict=$(grep -o "PASSED\|FAILED" "$dir/$clip.log" | head -1)
    [ "$clip" != stand ] && [ "$one_foot" = no ] && expected=FAILED
    echo "$name: $clip ${verdict:-no verdict} (expected $expected)"
    [ "$verdict" = "$expected" ] || { grep -E "FAIL " "$dir/$clip.log" | head -3; fail "$name: $clip"; }
  done
}

robot g1 "$data/robots/unitree_g1/g1_29dof_rev_1_0.urdf" "$data/robots" 5 yes
robot h1 "$data/robots/unitree_h1/h1_description/urdf/h1.urdf" "$data/robots/unitree_h1" 0 no
exit $status

#!/usr/bin/env bash
# cluster_test.sh slurm|parallel RETARGET EXAMPLES SCRATCH
#
# Converts the example clips (EXAMPLES/clips) and a broken file for humanoid25 with --check once on this machine
# (`retarget batch`) and once through a cluster script of EXAMPLES/cluster: local_slurm.sh with 3
# shards (a private Slurm, slurm_array.sh and the dependent merge job) or parallel.sh with 2
# shards (GNU parallel, then merge-summaries). Passes when the merged summary has the same clips
# as the single run with the same status, output frames, source frames and check outcome each,
# and when it was merged from every shard. Exits 77 (skip) where the scheduler is unavailable.
set -euo pipefail
mode=${1:?mode: slurm or parallel}
retarget=${2:?retarget binary}
examples=${3:?examples folder}
scratch=${4:?scratch folder}
robot=humanoid25   # the project's own robot: no ../shared data needed

rm -rf "$scratch"
mkdir -p "$scratch/in"
# The example clips plus one broken file: a shard that exits 2 must not keep the merge from
# running (afterany), and its failure must reach the merged summary and the exit status.
cp "$examples"/clips/*.bvh "$scratch/in/"
printf 'HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 x\n' >"$scratch/in/broken.bvh"
PATH=$(dirname "$retarget"):$PATH
export PATH

case "$mode" in
  slurm) shards=3 ;;
  parallel)
    shards=2
    parallel --version 2>/dev/null | grep -q "^GNU parallel" ||
      { echo "SKIP: GNU parallel is not installed (apt-get install parallel; moreutils' parallel is another tool)"; exit 77; } ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac

start=$SECONDS
set +e
"$retarget" batch "$scratch/in" --robot "$robot" -o "$scratch/single" --check --format csv,npz -q
single_rc=$?
set -e
echo "single-machine batch: exit $single_rc in $((SECONDS - start)) s"

start=$SECONDS
set +e
if [ "$mode" = slurm ]; then
  LOCAL_SLURM_TIMEOUT=600 RETARGET="$retarget" bash "$examples/cluster/local_slurm.sh" \
    "$scratch/in" "$scratch/cluster" "$shards" "$robot"
else
  JOBS_PER_SHARD=1 bash "$examples/cluster/parallel.sh" "$scratch/in" "$scratch/cluster" "$shards" "$robot"
fi
cluster_rc=$?
set -e
echo "$mode: exit $cluster_rc in $((SECONDS - start)) s"
if [ "$cluster_rc" -eq 77 ]; then echo "SKIP: Slurm cannot run on this machine (see the local_slurm line above)"; exit 77; fi

python3 - "$scratch/single/summary.json" "$scratch/cluster/summary.json" "$shards" "$single_rc" "$cluster_rc" <<'PY'
import json, sys
single_path, merged_path, shards, single_rc, cluster_rc = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
try:
    merged = json.load(open(merged_path))
except OSError as e:
    sys.exit(f"FAIL: no merged summary: {e}")
single = json.load(open(single_path))
fields = ("status", "frames", "source_frames", "check")
def table(s):
    return {c["name"]: tuple(c.get(f) for f in fields) for c in s["clips"]}
a, b = table(single), table(merged)
bad = []
if not a:
    bad.append("the single-machine batch converted no clip")
for name in sorted(set(a) | set(b)):
    if a.get(name) != b.get(name):
        bad.append(f"{name}: single {a.get(name)} vs cluster {b.get(name)} ({', '.join(fields)})")
if len(merged.get("merged_from", [])) != shards:
    bad.append(f"merged from {len(merged.get('merged_from', []))} summaries, expected {shards}")
if a.get("broken", ("",))[0] != "bad-input":
    bad.append(f"the broken file is {a.get('broken')} on one machine, expected bad-input")
if cluster_rc != single_rc:
    bad.append(f"exit status {cluster_rc} through the cluster, {single_rc} on one machine")
for name, row in sorted(b.items()):
    print(f"  {name}: " + ", ".join(f"{f}={v}" for f, v in zip(fields, row)))
if bad:
    print("FAIL:\n  " + "\n  ".join(bad))
    sys.exit(1)
print(f"OK: {len(b)} clip(s) identical (status, frames, source frames, check) through {shards} shards")
PY

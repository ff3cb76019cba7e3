#!/usr/bin/env bash
# Converting a motion library with GNU parallel: N shards spread over this machine or several
# (--sshloginfile), then one merge of the shard summaries.
#
#   examples/cluster/parallel.sh /data/mocap /shared/out/g1 8           # 8 shards here
#   SSHLOGINS=nodes.txt examples/cluster/parallel.sh /data/mocap /shared/out/g1 8
#
# With several machines, INPUT and OUTDIR must be on a filesystem they all share and `retarget`
# on every machine's PATH. Each shard writes summary-shard-I-of-N.* into OUTDIR; rerunning the
# script after an interruption skips every clip already finished.
set -euo pipefail

INPUT=${1:?usage: parallel.sh INPUT OUTDIR [SHARDS] [ROBOT]}
OUTDIR=${2:?usage: parallel.sh INPUT OUTDIR [SHARDS] [ROBOT]}
N=${3:-4}
ROBOT=${4:-g1}
JOBS_PER_SHARD=${JOBS_PER_SHARD:-2}   # worker processes per shard

remote=()
[ -n "${SSHLOGINS:-}" ] && remote=(--sshloginfile "$SSHLOGINS")

# --halt never: a shard that exits 1 or 2 (clip failures, recorded in its summary) must not stop
# the others. The exit status of parallel is the number of failed shards; the merge decides.
seq 1 "$N" | parallel "${remote[@]}" --halt never --line-buffer --tag \
  retarget batch "$INPUT" --robot "$ROBOT" -o "$OUTDIR" --check --shard {}/"$N" -j "$JOBS_PER_SHARD" -q || true

# 0: every clip ok; 1: some clip failed its check; 2: some clip failed otherwise or a shard is missing.
retarget merge-summaries "$OUTDIR" "$OUTDIR"

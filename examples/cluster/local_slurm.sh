#!/usr/bin/env bash
# Tries the Slurm path on one machine: brings up a private single-node Slurm (its own munged,
# slurmctld and slurmd on localhost, every file under a temporary folder), submits
# slurm_array.sh as an array of SHARDS tasks and the dependent merge job the way the README tells
# users to, waits for them, prints where the merged summary is and stops the daemons it started
# (also on failure or Ctrl-C). Nothing outside the temporary folder and OUTDIR is touched; an
# already configured Slurm on this machine is not used (SLURM_CONF points at the private one).
#
#   sudo examples/cluster/local_slurm.sh examples/clips /tmp/out-g1 3 g1
#
# Needs root (slurmd runs the jobs) and the Debian packages slurmctld, slurmd, slurm-client and
# munge (`apt-get install slurm-wlm munge`); `retarget` must be on PATH (or RETARGET=/path/to/it).
# The node is sized from nproc and the memory of this machine; when slurm_array.sh asks for more
# CPUs per task (--cpus-per-task=8) than nproc / SHARDS, the submission lowers it to that (at
# least 1), so that the tasks run side by side. Other sbatch settings can be given the usual way,
# through SBATCH_* variables (SBATCH_TIMELIMIT=12:00:00 for a library that needs more than the
# script's 4 hours per task).
#
# Exit status: that of the merge job (0 every clip ok, 1 some clip failed its check, 2 some clip
# failed otherwise or a shard is missing); 3 when sbatch rejected a submission (a broken #SBATCH
# line, say), the merge job could never run, or the jobs did not finish in LOCAL_SLURM_TIMEOUT
# seconds (default 0: no limit beyond the tasks' own --time); 77 when Slurm cannot run here at all
# (not root, packages missing, munged, slurmctld or slurmd would not start: their log tails are
# printed), which the tests read as "skip". KEEP_SLURM_DIR=1 keeps the
# temporary folder (config, state, daemon logs) for a look afterwards. The folder is made under
# $TMPDIR (default /tmp), which must allow executing files: slurmd runs the job scripts from its
# spool there.
set -euo pipefail

usage="usage: local_slurm.sh INPUT OUTDIR [SHARDS] [ROBOT]"
INPUT=${1:?$usage}
OUTDIR=${2:?$usage}
SHARDS=${3:-3}
ROBOT=${4:-g1}
TIMEOUT=${LOCAL_SLURM_TIMEOUT:-0}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

say() { echo "local_slurm: $*" >&2; }
cannot() { say "cannot run Slurm here: $*"; exit 77; }
die() { say "error: $*"; exit 3; }

[[ "$TIMEOUT" =~ ^[0-9]+$ ]] || { say "error: LOCAL_SLURM_TIMEOUT must be a number of seconds, got '$TIMEOUT'"; exit 2; }
[[ "$SHARDS" =~ ^[1-9][0-9]*$ ]] || { say "error: SHARDS must be a positive integer, got '$SHARDS'"; exit 2; }
[ -e "$INPUT" ] || { say "error: $INPUT: no such file or folder"; exit 2; }
INPUT=$(cd "$(dirname "$INPUT")" && pwd)/$(basename "$INPUT")
mkdir -p "$OUTDIR"
OUTDIR=$(cd "$OUTDIR" && pwd)

if [ -n "${RETARGET:-}" ]; then
  [ -x "$RETARGET" ] || { say "error: RETARGET=$RETARGET is not an executable"; exit 2; }
  PATH=$(cd "$(dirname "$RETARGET")" && pwd):$PATH
fi
command -v retarget >/dev/null || { say "error: retarget is not on PATH (build it, or set RETARGET=/path/to/retarget)"; exit 2; }
export PATH

[ "$(id -u)" -eq 0 ] || cannot "slurmd must run as root (try sudo)"
for tool in munged slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
  command -v "$tool" >/dev/null || cannot "$tool not found (apt-get install slurmctld slurmd slurm-client munge)"
done
command -v python3 >/dev/null || cannot "python3 not found (used to pick free ports)"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/local-slurm.XXXXXX")
chmod 700 "$tmp"
# The daemons this script started, killed in reverse order on exit. Each runs in its own session
# (setsid), so that a Ctrl-C in the terminal reaches this script, which then cancels the jobs
# while the daemons still run, rather than the daemons themselves.
pids=()
jobs_submitted=()

# The slurmstepd processes of this private Slurm: those with our slurmd.log open.
stepds() {
  local fd
  for fd in /proc/[0-9]*/fd/*; do
    [ "$(readlink "$fd" 2>/dev/null)" = "$tmp/log/slurmd.log" ] || continue
    fd=${fd#/proc/}
    echo "${fd%%/*}"
  done | sort -u | grep -vxF -e none "${pids[@]/#/-e}" || true
}

cleanup() {
  local rc=$?
  trap - EXIT INT TERM
  local i
  if ((${#jobs_submitted[@]})); then
    # Cancel, then give slurmd up to 20 s to end the jobs' steps while the controller still runs.
    timeout 10 scancel "${jobs_submitted[@]}" 2>/dev/null || true
    for _ in $(seq 100); do
      [ -z "$(timeout 5 squeue -h -o %i 2>/dev/null)" ] && [ -z "$(stepds)" ] && break
      sleep 0.2
    done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill -TERM "${pids[i]}" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "${pids[i]}" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "${pids[i]}" 2>/dev/null || true
    wait "${pids[i]}" 2>/dev/null || true
  done
  # A job step whose daemons went away before it ended (slurmstepd holds slurmd.log open).
  for i in $(stepds); do kill -KILL "$i" 2>/dev/null || true; done
  if [ "${KEEP_SLURM_DIR:-0}" = 1 ]; then say "kept $tmp"; else rm -rf "$tmp"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'say "interrupted"; exit 130' INT
trap 'say "terminated"; exit 143' TERM

show_logs() {
  for f in "$tmp"/log/*.log; do
    [ -s "$f" ] || continue
    say "--- last lines of $(basename "$f") ---"
    tail -n 15 "$f" >&2
  done
}

mkdir -p "$tmp"/{munge,state,spool,log}

# munge: a private key and socket, so neither the system's munged nor its key is involved.
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
setsid munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/socket" \
  --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/seed" --log-file="$tmp/log/munged.log" \
  2>>"$tmp/log/munged.log" &
pids+=($!)
for _ in $(seq 50); do [ -S "$tmp/munge/socket" ] && break; sleep 0.1; done
[ -S "$tmp/munge/socket" ] || { show_logs; cannot "munged did not start"; }

# The node: this machine's CPUs and memory (minus 10% and at least 512 MiB for the system).
host=$(hostname -s 2>/dev/null || uname -n)
host=${host%%.*}
cpus=$(nproc)
mem_mb=$(awk '/^MemTotal:/ { print int($2 / 1024) }' /proc/meminfo)
mem_mb=$((mem_mb - (mem_mb / 10 > 512 ? mem_mb / 10 : 512)))
((mem_mb >= 256)) || cannot "only $mem_mb MiB of memory for the node"
read -r ctld_port slurmd_port < <(python3 -c '
import socket
ss = [socket.socket() for _ in range(2)]
for s in ss: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in ss))')

export SLURM_CONF="$tmp/slurm.conf"
cat >"$SLURM_CONF" <<EOF
# Private single-node Slurm of local_slurm.sh (removed when it exits).
ClusterName=retarget-local
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/munge/socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool/slurmd-%n
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd-%n.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups: works in containers; the jobs' resources are accounted, not enforced.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
SchedulerType=sched/backfill
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
MinJobAge=3600
MaxArraySize=100001
NodeName=localnode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=local Nodes=localnode Default=YES MaxTime=INFINITE State=UP
EOF

setsid slurmctld -D -i -f "$SLURM_CONF" >>"$tmp/log/slurmctld.stderr.log" 2>&1 &
pids+=($!)
setsid slurmd -D -N localnode -f "$SLURM_CONF" >>"$tmp/log/slurmd.stderr.log" 2>&1 &
pids+=($!)

# Up when the node is idle (slurmd registered with slurmctld).
up=0
for _ in $(seq 300); do
  for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null || { show_logs; cannot "a Slurm daemon exited while starting (logs above)"; }; done
  state=$(sinfo -h -n localnode -o %T 2>/dev/null || true)
  if [ "$state" = idle ]; then up=1; break; fi
  sleep 0.2
done
((up)) || { show_logs; cannot "the node did not become idle in 60 s (state: ${state:-unknown}; logs above)"; }
version=$(sinfo -V)
say "$version up: node localnode with $cpus CPU(s), $mem_mb MiB; config and logs in $tmp"

# As the README says (Slurm arrays), with the CPUs per task lowered so that the tasks run side by
# side on this node (the shards writing into one folder at once, as on a cluster).
script_cpus=$(sed -n 's/^#SBATCH --cpus-per-task=\([0-9]*\).*/\1/p' "$here/slurm_array.sh")
script_mem=$(sed -n 's/^#SBATCH --mem-per-cpu=\([0-9]*\)G.*/\1/p' "$here/slurm_array.sh")
extra=()
task_cpus=${script_cpus:-1}
fit=$((cpus / SHARDS > 1 ? cpus / SHARDS : 1))
if ((task_cpus > fit)); then
  task_cpus=$fit
  extra+=(--cpus-per-task="$fit")
  say "slurm_array.sh asks for $script_cpus CPUs per task; $SHARDS tasks on $cpus CPUs: submitting with --cpus-per-task=$fit"
fi
if [ -n "$script_mem" ] && ((script_mem * 1024 * task_cpus > mem_mb)); then
  per_cpu=$((mem_mb / task_cpus))
  extra+=(--mem-per-cpu="${per_cpu}M")
  say "slurm_array.sh asks for ${script_mem}G per CPU; this node has $mem_mb MiB: submitting with --mem-per-cpu=${per_cpu}M"
fi

cd "$OUTDIR"   # the tasks' logs (--output=retarget-%A_%a.log) land here, as from a user's submit folder
jobid=$(sbatch --parsable "${extra[@]}" --array=1-"$SHARDS" "$here/slurm_array.sh" "$INPUT" "$OUTDIR" "$ROBOT") ||
  die "sbatch of slurm_array.sh failed"
jobs_submitted+=("$jobid")
mergeid=$(sbatch --parsable --dependency=afterany:"$jobid" --output=retarget-merge-%j.log \
  --wrap "retarget merge-summaries $OUTDIR $OUTDIR") || die "sbatch of the merge job failed"
jobs_submitted+=("$mergeid")
say "submitted array job $jobid ($SHARDS tasks) and merge job $mergeid (afterany:$jobid)"

# Wait for the merge job to end; scontrol keeps finished jobs for MinJobAge seconds.
field() { sed -n "s/.*[[:space:]]$1=\([^[:space:]]*\).*/\1/p" <<<"$2"; }
start=$SECONDS
last=""
while true; do
  info=$(scontrol -o show job "$mergeid" 2>/dev/null) || die "job $mergeid vanished"
  state=$(field JobState "$info")
  case "$state" in
    COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | PREEMPTED | BOOT_FAIL | DEADLINE) break ;;
  esac
  [ "$(field Reason "$info")" = DependencyNeverSatisfied ] && die "the merge job's dependency can never be satisfied"
  now=$(squeue -h -o '%i:%T' 2>/dev/null | tr '\n' ' ')
  [ "$now" != "$last" ] && say "queue: $now"
  last=$now
  ((TIMEOUT == 0 || SECONDS - start < TIMEOUT)) || die "the jobs did not finish in $TIMEOUT s (LOCAL_SLURM_TIMEOUT)"
  sleep 1
done
jobs_submitted=()

array_failed=0
while read -r line; do
  [ -n "$line" ] || continue
  say "task $(field ArrayJobId "$line")_$(field ArrayTaskId "$line"): $(field JobState "$line") exit $(field ExitCode "$line")"
  [ "$(field JobState "$line")" = COMPLETED ] || array_failed=1
done < <(scontrol -o show job "$jobid")
exit_code=$(field ExitCode "$info")
say "merge job $mergeid: $state exit $exit_code (log: $OUTDIR/retarget-merge-$mergeid.log)"
cat "$OUTDIR/retarget-merge-$mergeid.log" >&2 2>/dev/null || true
((array_failed)) && say "some array task did not exit 0 (see $OUTDIR/retarget-${jobid}_*.log)"
[ -f "$OUTDIR/summary.json" ] || die "no merged summary in $OUTDIR"
echo "merged summary: $OUTDIR/summary.json ($OUTDIR/summary.csv, $OUTDIR/index.html)"
rc=${exit_code%%:*}
[ "$state" = COMPLETED ] || [ "$state" = FAILED ] || rc=3
exit "$rc"

#!/usr/bin/env bash
# tools/slurm/chainsim-optimize.sbatch under a real Slurm: a one-node cluster
# (munged, slurmctld, slurmd) brought up in a temporary directory, a small
# search submitted with sbatch on 3 tasks (rank 0 and two MPI worker ranks),
# its history.csv (without wall_s) and best.yaml compared with the same
# search run locally with --workers 2; the same job submitted again with
# --generations 2 continues the search (--resume) and equals a local search
# of 2 generations; a job whose problem file is missing fails, saying so, and
# one whose problem file is malformed fails with chainsim's exit status 1.
#
#   slurm_test.sh CHAINSIM_EXE [SBATCH_SCRIPT]
#
# Exit 77 (ctest: SKIPPED) with the reason when not root or when slurm-wlm or
# munge are not installed (tools/setup.sh installs them); it installs
# nothing. The daemons and every process of the cluster's jobs are stopped
# and the temporary directory removed on any exit.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
CHAINSIM="${1:?usage: slurm_test.sh CHAINSIM_EXE [SBATCH_SCRIPT]}"
SCRIPT="${2:-$HERE/../../../tools/slurm/chainsim-optimize.sbatch}"
JOB_TIMEOUT_S="${CHAINSIM_SLURM_TEST_JOB_TIMEOUT_S:-300}" # per job
# CHAINSIM_SLURM_TEST_KEEP=1 keeps the temporary directory (logs, outputs) for a look
T0=$SECONDS

skip() {
  echo "SKIP: $*"
  exit 77
}
log() { echo "slurm_test [$((SECONDS - T0)) s]: $*"; }

# --- can it run here? ---------------------------------------------------------
[ "$(id -u)" -eq 0 ] || skip "needs root: it runs munged, slurmctld and slurmd itself (SlurmUser=root)"
missing=()
for c in slurmctld slurmd sbatch sinfo squeue scontrol scancel; do command -v "$c" >/dev/null || missing+=("$c"); done
[ ${#missing[@]} -eq 0 ] || skip "slurm-wlm is not installed (no ${missing[*]}); tools/setup.sh installs it"
command -v munged >/dev/null || skip "munge is not installed (no munged); tools/setup.sh installs it"

fail() {
  echo "FAIL: $*" >&2
  exit 1
}
[ -x "$CHAINSIM" ] || fail "no chainsim executable at $CHAINSIM"
CHAINSIM="$(cd "$(dirname "$CHAINSIM")" && pwd)/$(basename "$CHAINSIM")"
[ -f "$SCRIPT" ] || fail "no job script at $SCRIPT"
SCRIPT="$(cd "$(dirname "$SCRIPT")" && pwd)/$(basename "$SCRIPT")"
command -v mpirun >/dev/null || fail "no mpirun (openmpi-bin): chainsim optimize needs it under Slurm"
command -v python3 >/dev/null || fail "no python3 (used to find free ports)"

# nothing from a surrounding Slurm job or the caller's settings
while read -r v; do unset "$v"; done < <(compgen -e | grep -E '^(SLURM|SBATCH|SALLOC|SRUN)_' || true)
unset CHAINSIM_PROBLEM CHAINSIM_OUT CHAINSIM_WORKERS MPIRUN CHAINSIM_MPIRUN_ARGS

# under /tmp, not TMPDIR: munged wants every directory above its socket
# searchable by all
TMP="$(mktemp -d /tmp/chainsim-slurm.XXXXXX)"
chmod 755 "$TMP"
mkdir -p "$TMP"/{run,munge,state,spool,log,problem,jobs}
chmod 700 "$TMP/munge"
export SLURM_CONF="$TMP/slurm.conf"
MUNGE_SOCKET="$TMP/run/munge.sock"
munged_pid="" slurmctld_pid="" slurmd_pid=""

# --- cleanup, on every exit -------------------------------------------------
stop_pid() { # PID NAME: TERM, then KILL after 10 s
  local pid="$1"
  if [ -z "$pid" ] || ! kill -0 "$pid" 2>/dev/null; then return 0; fi
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 100); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "slurm_test: $2 (pid $pid) did not stop on SIGTERM: SIGKILL" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}
# processes started by this cluster: slurmstepd and the jobs' processes
# inherit SLURM_CONF=$TMP/slurm.conf (the daemons' and sbatch's environment)
cluster_pids() {
  local p
  for p in /proc/[0-9]*; do
    p="${p#/proc/}"
    [ "$p" = "$$" ] || [ "$p" = "$BASHPID" ] && continue
    tr '\0' '\n' 2>/dev/null <"/proc/$p/environ" | grep -qxF "SLURM_CONF=$SLURM_CONF" && echo "$p"
  done
  return 0
}
dump_logs() {
  local f
  for f in "$TMP"/log/* "$TMP"/jobs/*.out; do
    [ -f "$f" ] || continue
    echo "----- ${f#"$TMP"/} (last 80 lines) -----" >&2
    tail -n 80 "$f" >&2
  done
}
cleanup() {
  local rc=$? jobs p
  trap - EXIT INT TERM
  set +e
  [ $rc -eq 0 ] || [ $rc -eq 77 ] || dump_logs
  if [ -n "$slurmctld_pid" ] && kill -0 "$slurmctld_pid" 2>/dev/null; then
    jobs="$(squeue -h -o %i 2>/dev/null)"
    if [ -n "$jobs" ]; then
      # shellcheck disable=SC2086
      scancel $jobs 2>/dev/null
      for _ in $(seq 50); do
        [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
        sleep 0.2
      done
    fi
  fi
  stop_pid "$slurmd_pid" slurmd
  stop_pid "$slurmctld_pid" slurmctld
  stop_pid "$munged_pid" munged
  for p in $(cluster_pids); do kill -KILL "$p" 2>/dev/null && echo "slurm_test: killed leftover process $p" >&2; done
  if [ "${CHAINSIM_SLURM_TEST_KEEP:-0}" = 1 ]; then
    log "daemons stopped; kept $TMP (CHAINSIM_SLURM_TEST_KEEP=1)"
  else
    rm -rf "$TMP"
  fi
  log "cleaned up (exit $rc)"
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# --- munge --------------------------------------------------------------------
if command -v mungekey >/dev/null; then
  mungekey --create --keyfile="$TMP/munge/munge.key" --force
else
  dd if=/dev/urandom of="$TMP/munge/munge.key" bs=1 count=1024 status=none
fi
chmod 400 "$TMP/munge/munge.key"
munged --foreground --force --socket="$MUNGE_SOCKET" --key-file="$TMP/munge/munge.key" \
  --pid-file="$TMP/run/munged.pid" --log-file="$TMP/log/munged.log" --seed-file="$TMP/munge/munged.seed" \
  >"$TMP/log/munged.out" 2>&1 &
munged_pid=$!
for _ in $(seq 100); do
  [ -S "$MUNGE_SOCKET" ] && break
  kill -0 "$munged_pid" 2>/dev/null || fail "munged exited at once"
  sleep 0.1
done
[ -S "$MUNGE_SOCKET" ] || fail "munged made no socket at $MUNGE_SOCKET within 10 s"

# --- slurm.conf: one node, this host --------------------------------------------
NODE="$(hostname -s)"
# the hardware as slurmd sees it (CPUs, sockets, cores, threads), without RealMemory
HW="$(slurmd -C | head -n 1 | tr ' ' '\n' | grep -E '^(CPUs|Boards|SocketsPerBoard|CoresPerSocket|ThreadsPerCore)=' | tr '\n' ' ')"
[ -n "$HW" ] || HW="CPUs=$(nproc)"
read -r CTLD_PORT SLURMD_PORT < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
: >"$TMP/plugstack.conf"
cat >"$SLURM_CONF" <<EOF
# a one-node cluster for tests/tools/slurm/slurm_test.sh
ClusterName=chainsimtest
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCKET
StateSaveLocation=$TMP/state
SlurmdSpoolDir=$TMP/spool
SlurmctldPidFile=$TMP/run/slurmctld.pid
SlurmdPidFile=$TMP/run/slurmd.pid
SlurmctldLogFile=$TMP/log/slurmctld.log
SlurmdLogFile=$TMP/log/slurmd.log
PlugStackConfig=$TMP/plugstack.conf
MailProg=/bin/true
# containers: no cgroups
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=600
NodeName=$NODE NodeAddr=127.0.0.1 $HW State=UNKNOWN
PartitionName=test Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
log "cluster: node $NODE ($HW), slurmctld port $CTLD_PORT, slurmd port $SLURMD_PORT, in $TMP"

slurmctld -D -f "$SLURM_CONF" >"$TMP/log/slurmctld.out" 2>&1 &
slurmctld_pid=$!
slurmd -D -f "$SLURM_CONF" >"$TMP/log/slurmd.out" 2>&1 &
slurmd_pid=$!
state=""
for _ in $(seq 120); do
  kill -0 "$slurmctld_pid" 2>/dev/null || fail "slurmctld exited"
  kill -0 "$slurmd_pid" 2>/dev/null || fail "slurmd exited"
  state="$(sinfo -h -n "$NODE" -o %T 2>/dev/null || true)"
  [ "$state" = "idle" ] && break
  sleep 0.5
done
[ "$state" = "idle" ] || fail "node $NODE not idle within 60 s (sinfo says '${state:-nothing}')"
log "node $NODE is idle"

# --- the problem: three rotation modules crawling 0.4 s (as the optimize tests) ---
cat >"$TMP/problem/base.yaml" <<'EOF'
name: slurm-test
duration_s: 0.4
chain: RRR
central:
  params: {gait: 1, amplitude_cdeg: 3000, omega_mrad_s: 8000, phase_mrad: 1000, posture_cdeg: 5000}
output: {trace_hz: 50}
EOF
cat >"$TMP/problem/gait.yaml" <<'EOF'
name: slurm-test-gait
scene: base.yaml
genome:
  params:
    - {target: central.amplitude_cdeg, min: 1000, max: 5000, step: 2000}
    - {target: central.omega_mrad_s, min: 4000, max: 12000, step: 4000}
    - {target: central.phase_mrad, min: 500, max: 1500, step: 500}
measures:
  x: {kind: distance, of: chain, along: x}
  head_x: {kind: distance, of: head, along: x}
objective:
  maximize: x
ga: {population: 4, generations: 1, seed: 1}
EOF
PROBLEM="$TMP/problem/gait.yaml"
# a malformed one: every rank refuses it, chainsim exits 1
sed 's/step: 2000}/stpe: 2000}/' "$PROBLEM" >"$TMP/problem/malformed.yaml"

# --- jobs -----------------------------------------------------------------------
# submit NAME SBATCH_SCRIPT_ARGS...: the job id; its output in jobs/NAME.out.
# Three tasks on a node of two CPUs: --overcommit. The job's mpirun starts an
# orted with srun on this node too (ras_base_launch_orted_on_hn), the way it
# reaches the other nodes of a bigger allocation.
submit() {
  local name="$1"
  shift
  local id
  id="$(CHAINSIM="$CHAINSIM" CHAINSIM_MPIRUN_ARGS="--mca ras_base_launch_orted_on_hn 1" \
    sbatch --parsable --job-name="chainsim-$name" --ntasks=3 --overcommit --time=10 \
    --chdir="$TMP/jobs" --output="$TMP/jobs/$name.out" "$SCRIPT" "$@")" || return 1
  id="${id%%;*}"
  [ -n "$id" ] || return 1
  echo "$id"
}
# wait_job ID: waits until it ends (JOB_TIMEOUT_S at most, then cancels it);
# sets JOB_STATE and JOB_CODE (scontrol's JobState and ExitCode)
wait_job() {
  local info t_end=$((SECONDS + JOB_TIMEOUT_S))
  while :; do
    info="$(scontrol show job -o "$1" 2>/dev/null || true)"
    JOB_STATE="$(grep -o 'JobState=[A-Z_]*' <<<"$info" | cut -d= -f2 || true)"
    JOB_CODE="$(grep -o 'ExitCode=[0-9:]*' <<<"$info" | cut -d= -f2 || true)"
    case "$JOB_STATE" in
      COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE | PREEMPTED) return 0 ;;
    esac
    if [ $SECONDS -ge $t_end ]; then
      echo "slurm_test: job $1 not finished within $JOB_TIMEOUT_S s; scontrol show job:" >&2
      echo "$info" >&2
      scancel "$1" 2>/dev/null || true
      JOB_STATE="UNFINISHED(cancelled_after_${JOB_TIMEOUT_S}_s)" JOB_CODE="-"
      return 0
    fi
    sleep 0.5
  done
}
# expect_end ID STATE EXITCODE WHAT: the job ended so
expect_end() {
  wait_job "$1"
  if [ "$JOB_STATE" != "$2" ] || [ "$JOB_CODE" != "$3" ]; then
    fail "$4: job $1 ended $JOB_STATE, exit code $JOB_CODE (expected $2 $3)"
  fi
  log "job $1 ($4): $JOB_STATE $JOB_CODE"
}
history_without_wall() { sed 's/,[^,]*$//' "$1"; }
expect_same_search() { # DIR_FROM_SLURM LOCAL_DIR WHAT
  [ -f "$1/history.csv" ] || fail "$3: no $1/history.csv"
  diff <(history_without_wall "$2/history.csv") <(history_without_wall "$1/history.csv") >&2 ||
    fail "$3: history.csv (without wall_s) differs from the local search's (< local, > Slurm)"
  diff "$2/best.yaml" "$1/best.yaml" >&2 || fail "$3: best.yaml differs from the local search's (< local, > Slurm)"
}

# 1. a job whose problem file does not exist fails, saying so; a job whose
# search fails (a malformed problem file) fails with chainsim's exit status
id_missing="$(submit missing "$TMP/problem/no-such-problem.yaml" "$TMP/out-missing")" || fail "sbatch failed"
id_malformed="$(submit malformed "$TMP/problem/malformed.yaml" "$TMP/out-malformed")" || fail "sbatch failed"
expect_end "$id_missing" FAILED 1:0 "missing problem file"
grep -q "no-such-problem.yaml does not exist" "$TMP/jobs/missing.out" ||
  fail "the job with a missing problem file did not say so in its output"
expect_end "$id_malformed" FAILED 1:0 "malformed problem file"
grep -q "malformed.yaml:.*unknown key 'stpe'" "$TMP/jobs/malformed.out" ||
  fail "the job with a malformed problem file did not show chainsim's message"

# 2. the search on 3 tasks: rank 0 and two worker ranks
id="$(submit search "$PROBLEM" "$TMP/out-slurm")" || fail "sbatch failed"
expect_end "$id" COMPLETED 0:0 "search on 3 tasks"
grep -q "2 MPI worker ranks" "$TMP/jobs/search.out" || fail "the search job did not run on 2 MPI worker ranks"

"$CHAINSIM" optimize "$PROBLEM" --out "$TMP/out-local" --workers 2 >"$TMP/log/local.out" 2>&1 ||
  { cat "$TMP/log/local.out" >&2; fail "the local search failed"; }
expect_same_search "$TMP/out-slurm" "$TMP/out-local" "generation 0..1"
log "history.csv and best.yaml equal the local search's (--workers 2)"

# 3. submitted again into the same directory with one more generation: the
# script continues the search (--resume); it ends as a search of 2 generations
id="$(submit resume "$PROBLEM" "$TMP/out-slurm" --generations 2)" || fail "sbatch failed"
expect_end "$id" COMPLETED 0:0 "the search again, --generations 2"
grep -q "already holds a search: continuing it (--resume)" "$TMP/jobs/resume.out" ||
  fail "the job script did not pass --resume for a directory holding a search"
"$CHAINSIM" optimize "$PROBLEM" --out "$TMP/out-local-2" --workers 2 --generations 2 >"$TMP/log/local-2.out" 2>&1 ||
  { cat "$TMP/log/local-2.out" >&2; fail "the local search of 2 generations failed"; }
expect_same_search "$TMP/out-slurm" "$TMP/out-local-2" "resumed to generation 2"
[ "$(history_without_wall "$TMP/out-slurm/history.csv" | wc -l)" -eq 13 ] ||
  fail "the resumed history has not 1 + 3 x 4 rows"
log "the resumed search equals the local search of 2 generations"

log "PASS"

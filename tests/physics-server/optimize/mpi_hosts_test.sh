#!/usr/bin/env bash
# `chainsim optimize` under mpirun across hosts, the hosts simulated with
# Linux namespaces (physics-server/optimize/mpi_pool.cpp; docs/optimize.md,
# "Across hosts"):
#
#   mpi_hosts_test.sh CHAINSIM [MPIRUN]
#
# Three hosts A, B, C: each a network namespace with its own address on
# 10.77.0.0/24 (a veth to a bridge that lives in a fourth namespace, so the
# root namespace is not touched) and, for every process mpirun starts there,
# a UTS namespace with its own host name. mpirun runs on A (rank 0) and
# starts its daemons (orted) on B and C through netns_rsh.sh in place of
# ssh; OpenMPI is held to TCP on that subnet. The search (3 rotation
# modules, runs of 10 s, one trial per individual, population 6,
# generations 0..2, no verification) is first run locally with --workers 2:
# its history.csv (without wall_s) is the reference that every search below
# must end with.
#
#   1. ranks 0, 1, 2 on hosts A, B, C: the same history;
#   2. rank 2's process killed on C in the middle of an evaluation (C's
#      daemon lives on): rank 0 names it after --rank-timeout ("rank 2 (pid
#      N on HOSTNAME-C) sent nothing for 8 s while evaluating; its evaluation
#      of KEY goes to another rank"), the search ends, mpirun exits 0, the
#      same history;
#   3. host C lost in the middle of an evaluation (every process in its
#      namespace SIGKILLed, its orted among them). OpenMPI 4.1.4 then does
#      one of two things, at random (docs/optimize.md, "Across hosts"), and
#      the test accepts either:
#      - it ends the whole job: mpirun must exit non-zero within 60 s, the
#        launcher naming the host; then `--resume` on A and B simulates the
#        individual C was evaluating and ends with the same history;
#      - the job goes on: rank 0 names rank 2 as in 2, the search ends with
#        the same history, and mpirun waits forever for the lost daemon's
#        rank: the test interrupts it (SIGINT) and it must exit.
#
# Exit 0 passed, 1 failed, 77 skipped (not root, no network namespaces, no
# mpirun). Namespaces, links, processes and the temporary directory are
# removed on every exit (set KEEP=1 to keep the directory); namespaces left
# by a run that was SIGKILLed are removed by the next run.
set -uo pipefail
PATH=$PATH:/usr/sbin:/sbin   # ip(8), when ctest runs without them

CHAINSIM=${1:?usage: mpi_hosts_test.sh CHAINSIM [MPIRUN]}
MPIRUN=${2:-mpirun}
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
AGENT="$HERE/netns_rsh.sh"
P="chainsim-mpih-$$"            # namespace names: $P-sw (the bridge), $P-a, $P-b, $P-c
SUBNET=10.77.0.0/24
RANK_TIMEOUT=8                  # --rank-timeout: a remote rank's death is seen only by its silence
RUN_TIMEOUT=90                  # any one search, then it is killed
DEADLINE=500                    # the whole test (ctest's TIMEOUT is 600: it would SIGKILL, leaving all this behind)
OPTS=(--no-replay --verify-top 0)
T0=$(date +%s.%N)
T=""

log() { printf '[%6.1f s] %s\n' "$(awk -v a="$T0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')" "$*"; }
skip() { echo "SKIPPED: $*"; exit 77; }
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }
# seconds a search may take: RUN_TIMEOUT, less if the deadline is nearer
budget() {
  local b
  b=$(awk -v a="$T0" -v b="$(date +%s.%N)" -v d="$DEADLINE" -v r="$RUN_TIMEOUT" \
        'BEGIN { x = int(d - (b - a)) - 10; print (x < r ? x : r) }')
  [ "$b" -gt 0 ] || fail "over the test's deadline of $DEADLINE s"
  echo "$b"
}

our_namespaces() { ip netns list 2>/dev/null | awk '{ print $1 }' | grep -E "^$1-(sw|a|b|c|probe)$"; }

# every process of the namespaces of prefix $1 killed, the namespaces deleted
remove_hosts() {
  local ns tries
  for tries in 1 2 3 4 5 6 7 8 9 10; do
    local left=0
    for ns in $(our_namespaces "$1"); do
      local pids
      pids=$(ip netns pids "$ns" 2>/dev/null)
      [ -n "$pids" ] && { left=1; kill -9 $pids 2>/dev/null; }
    done
    [ $left = 0 ] && break
    sleep 0.2
  done
  for ns in $(our_namespaces "$1"); do ip netns del "$ns" 2>/dev/null; done
}

cleanup() {
  trap - EXIT INT TERM HUP
  remove_hosts "$P"
  if [ -n "$T" ] && [ -d "$T" ]; then
    if [ "${KEEP:-0}" = 1 ]; then echo "kept $T"; else rm -rf "$T"; fi
  fi
}

# --- what is needed -----------------------------------------------------------
[ "$(id -u)" = 0 ] || skip "needs root: network namespaces (ip netns add) and veth links"
for tool in ip unshare timeout awk; do
  command -v "$tool" >/dev/null || skip "needs $tool"
done
command -v "$MPIRUN" >/dev/null || skip "no $MPIRUN"
[ -x "$CHAINSIM" ] || fail "$CHAINSIM is not an executable"
[ -x "$AGENT" ] || fail "$AGENT is not executable"

trap cleanup EXIT
trap 'echo "FAIL: interrupted" >&2; exit 130' INT TERM HUP

# namespaces and directories of an earlier run that was killed before it could clean up
stale() { [ "$1" != $$ ] && ! grep -qs mpi_hosts_test "/proc/$1/cmdline"; }
for ns in $(ip netns list 2>/dev/null | awk '{ print $1 }' | grep -E '^chainsim-mpih-[0-9]+-(sw|a|b|c|probe)$'); do
  pid=${ns#chainsim-mpih-}
  pid=${pid%%-*}
  if stale "$pid"; then
    echo "removing namespaces left by run $pid"
    remove_hosts "chainsim-mpih-$pid"
  fi
done
for d in /tmp/chainsim-mpih-*.*; do
  [ -d "$d" ] || continue
  pid=${d#/tmp/chainsim-mpih-}
  pid=${pid%%.*}
  stale "$pid" && rm -rf "$d"
done

out=$(ip netns add "$P-probe" 2>&1) || skip "ip netns add failed: $out"
out=$(ip -n "$P-probe" link add br0 type bridge 2>&1) || skip "no bridge in a network namespace: $out"
out=$(ip -n "$P-probe" link add v0 type veth peer name v1 2>&1) || skip "no veth pair: $out"
out=$(ip netns exec "$P-probe" unshare --uts /bin/sh -c 'hostname probe && hostname' 2>&1) ||
  skip "no UTS namespace (unshare --uts): $out"
ip netns del "$P-probe"

T=$(mktemp -d "/tmp/chainsim-mpih-$$.XXXXXX")
log "chainsim: $CHAINSIM; $("$MPIRUN" --version 2>/dev/null | head -1); work in $T"

# --- the hosts --------------------------------------------------------------
SW="$P-sw"
ip netns add "$SW" || fail "ip netns add $SW"
ip -n "$SW" link set lo up
ip -n "$SW" link add br0 type bridge || fail "bridge"
ip -n "$SW" link set br0 up
: >"$T/hosts.map"
i=1
for h in a b c; do
  ns="$P-$h"
  ip netns add "$ns" || fail "ip netns add $ns"
  ip -n "$SW" link add "v$h" type veth peer name eth0 netns "$ns" || fail "veth to $ns"
  ip -n "$SW" link set "v$h" master br0
  ip -n "$SW" link set "v$h" up
  ip -n "$ns" addr add "10.77.0.$i/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
  echo "10.77.0.$i $ns mpih-$$-$h" >>"$T/hosts.map"
  i=$((i + 1))
done
HOST_A=mpih-$$-a HOST_C=mpih-$$-c
printf '10.77.0.1 slots=1\n10.77.0.2 slots=1\n10.77.0.3 slots=1\n' >"$T/hosts-abc"
printf '10.77.0.1 slots=1\n10.77.0.2 slots=1\n' >"$T/hosts-ab"
log "hosts: $(awk '{ printf "%s%s = %s (%s)", (NR > 1 ? ", " : ""), $3, $1, $2 }' "$T/hosts.map")"

# --- the problem ----------------------------------------------------------------
cat >"$T/base.yaml" <<'EOF'
# three rotation modules crawling in open air (the optimize tests' base scene, runs of 10 s)
name: mpi-hosts-test
duration_s: 10.0
chain: RRR
central:
  params: {gait: 1, amplitude_cdeg: 3000, omega_mrad_s: 8000, phase_mrad: 1000, posture_cdeg: 5000}
output: {trace_hz: 50}
EOF
cat >"$T/gait.yaml" <<'EOF'
name: mpi-hosts-gait
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
ga: {population: 6, generations: 2, seed: 1}
evaluation: {trials: 1}
EOF
PROBLEM="$T/gait.yaml"

history_of() { awk '{ sub(/,[^,]*$/, ""); print }' "$1/history.csv"; }   # without wall_s
journaled() { tail -n +2 "$1/evaluations.jsonl" 2>/dev/null | grep -c '"key"'; }
has_key() { grep -qF "{\"key\":\"$2\"," "$1/evaluations.jsonl"; }

# the run's stderr, shown when a check fails
show() {
  echo "---- $1" >&2
  cat "$1" >&2
  echo "----" >&2
}

t=$(date +%s.%N)
tmo=$(budget) || exit 1
timeout -k 5 "$tmo" "$CHAINSIM" optimize "$PROBLEM" --out "$T/local" --workers 2 "${OPTS[@]}" >"$T/local.txt" 2>&1 ||
  { show "$T/local.txt"; fail "the local search failed"; }
history_of "$T/local" >"$T/reference.csv"
rows=$(($(wc -l <"$T/reference.csv") - 1))
[ "$rows" = 18 ] || fail "the local search has $rows rows, not 18"
log "local search (--workers 2): $rows rows, $(elapsed "$t") s"

# mpirun on host A in the background: mpirun_on_a HOSTFILE NP OUT ERR [chainsim options...]; sets MPI_PID
mpirun_on_a() {
  local hostfile=$1 np=$2 out=$3 err=$4 tmo
  shift 4
  tmo=$(budget) || exit 1
  NETNS_RSH_HOSTS="$T/hosts.map" NETNS_RSH_LOG="$T/launches.log" \
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
    ip netns exec "$P-a" unshare --uts /bin/sh -c 'hostname "$0" && exec "$@"' "$HOST_A" \
    timeout -k 5 "$tmo" "$MPIRUN" --allow-run-as-root --hostfile "$hostfile" -np "$np" \
    --mca plm_rsh_agent "$AGENT" \
    --mca btl tcp,self --mca btl_tcp_if_include "$SUBNET" --mca oob_tcp_if_include "$SUBNET" \
    --enable-recovery --mca orte_abort_on_non_zero_status 0 \
    "$CHAINSIM" optimize "$PROBLEM" --out "$out" "${OPTS[@]}" --rank-timeout "$RANK_TIMEOUT" "$@" \
    >"$err" 2>&1 &
  MPI_PID=$!
}

# no process left on any host, within 10 s of mpirun's end
hosts_are_empty() {
  local n h
  for n in $(seq 50); do
    local any=""
    for h in a b c; do any="$any$(ip netns pids "$P-$h")"; done
    [ -z "$any" ] && return 0
    sleep 0.2
  done
  for h in a b c; do
    echo "left on host $h: $(ip netns pids "$P-$h" | xargs -r ps -o pid=,args= -p)" >&2
  done
  return 1
}

comm_of() { cat "/proc/$1/comm" 2>/dev/null; }

# waits until host C is in the middle of a simulation (a firmware process of
# it runs there) and the journal has a result; 1 if mpirun ended first (or
# after 60 s)
wait_c_busy() {
  local out=$1 n p
  for n in $(seq 1200); do
    kill -0 "$MPI_PID" 2>/dev/null || return 1
    if [ "$(journaled "$out")" -ge 1 ]; then
      for p in $(ip netns pids "$P-c"); do
        case "$(comm_of "$p")" in fw-*) return 0 ;; esac
      done
    fi
    sleep 0.05
  done
  return 1
}

# the key of the individual host C's rank 2 is evaluating (from its work
# directory's scene, as scene/'s write_scene writes it: the names are the
# scene's only keys of those names, in block or flow style)
key_on_c() {
  local scene
  scene=$(ls "$1"/work/rank-2/*/scene.yaml 2>/dev/null | head -1)
  [ -n "$scene" ] || return 1
  awk 'function value(name,   v) {
         if (match($0, name ": *-?[0-9]+")) { v = substr($0, RSTART, RLENGTH); sub(/.*: */, "", v); return v }
         return ""
       }
       { if ((v = value("amplitude_cdeg")) != "") a = v
         if ((v = value("omega_mrad_s")) != "") o = v
         if ((v = value("phase_mrad")) != "") p = v }
       END {
         if (a == "" || o == "" || p == "") exit 1
         printf "central.amplitude_cdeg=%s central.omega_mrad_s=%s central.phase_mrad=%s\n", a, o, p
       }' "$scene"
}

# --- 1. ranks on hosts A, B, C ----------------------------------------------------
t=$(date +%s.%N)
: >"$T/launches.log"
mpirun_on_a "$T/hosts-abc" 3 "$T/abc" "$T/abc.txt"
wait "$MPI_PID"
rc=$?
[ $rc = 0 ] || { show "$T/abc.txt"; fail "mpirun across hosts A, B, C exited $rc"; }
grep -q "2 MPI worker ranks" "$T/abc.txt" || { show "$T/abc.txt"; fail "not 2 worker ranks"; }
[ "$(awk '{ print $1 }' "$T/launches.log" | sort | tr '\n' ' ')" = "10.77.0.2 10.77.0.3 " ] ||
  { cat "$T/launches.log"; fail "the daemons were not launched on B and C (launches above)"; }
history_of "$T/abc" | diff "$T/reference.csv" - >&2 || { show "$T/abc.txt"; fail "history across hosts differs from the local one"; }
hosts_are_empty || fail "processes left after the search across hosts"
log "1. ranks 0, 1, 2 on hosts A, B, C (daemons on B and C through netns_rsh.sh, TCP only): the local history; $(elapsed "$t") s"

# --- 2. rank 2's process killed on host C -------------------------------------------
# a kill that lands after the evaluation's result has gone loses nothing and the
# search ends before rank 2's silence is noticed: then it is tried again (3 times)
for attempt in 1 2 3; do
  t=$(date +%s.%N)
  out="$T/rank$attempt" err="$T/rank$attempt.txt"
  mpirun_on_a "$T/hosts-abc" 3 "$out" "$err"
  wait_c_busy "$out" || { wait "$MPI_PID"; show "$err"; fail "host C was never seen evaluating"; }
  victim=""
  for p in $(ip netns pids "$P-c"); do
    [ "$(comm_of "$p")" = chainsim ] && tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=2 &&
      victim=$p
  done
  [ -n "$victim" ] || { show "$err"; fail "no rank 2 on host C"; }
  kill -9 "$victim"
  tk=$(date +%s.%N)
  wait "$MPI_PID"
  rc=$?
  grep -q "optimize: rank 2 (pid " "$err" && break
  log "2. attempt $attempt: the search ended before rank 2's death was seen; again"
done
[ $rc = 0 ] || { show "$err"; fail "mpirun exited $rc after rank 2 was killed"; }
named="optimize: rank 2 (pid $victim on $HOST_C) sent nothing for $RANK_TIMEOUT s while evaluating; its evaluation of "
grep -qF "$named" "$err" || { show "$err"; fail "rank 2's loss is not named as: $named..."; }
grep "optimize: rank 2 (pid" "$err" | grep -q " goes to another rank$" || { show "$err"; fail "rank 2's work is not given to another rank"; }
history_of "$out" | diff "$T/reference.csv" - >&2 || { show "$err"; fail "history after losing rank 2 differs from the local one"; }
hosts_are_empty || fail "processes left after the search that lost rank 2"
log "2. rank 2 (pid $victim on $HOST_C) killed: $(grep -o 'optimize: rank 2 (pid.*' "$err")"
log "   search ended, mpirun exit 0 $(elapsed "$tk") s after the kill; the local history; $(elapsed "$t") s in all"

# --- 3. host C lost ----------------------------------------------------------------------
# OpenMPI 4.1.4 does one of two things (which one depends on which of its two
# notices of the loss it handles first: its launcher process for C ends, or
# its TCP connection to C's orted drops; both come at once here):
#   ended: mpirun ends the whole job within seconds, exit status not 0; then
#          --resume on A and B does the lost evaluation and ends the search;
#   on:    the job goes on; rank 0 gives rank 2 up after --rank-timeout, has
#          its evaluation done by rank 1 and ends the search; mpirun then
#          waits for the lost daemon's rank forever: the test interrupts it
#          (SIGINT, as Ctrl-C) once rank 0 has been gone 10 s.
# As in 2, a kill that lands after C's evaluation has sent its result (so
# that nothing was lost) is tried again, at most 3 times.
alive() { [ -e "/proc/$1" ] && ! grep -qE '^[0-9]+ \(.*\) [ZX]' "/proc/$1/stat" 2>/dev/null; }
path=""
for attempt in 1 2 3; do
  t=$(date +%s.%N)
  out="$T/host$attempt" err="$T/host$attempt.txt"
  mpirun_on_a "$T/hosts-abc" 3 "$out" "$err"
  wait_c_busy "$out" || { wait "$MPI_PID"; show "$err"; fail "host C was never seen evaluating"; }
  rank0=""
  for p in $(ip netns pids "$P-a"); do
    [ "$(comm_of "$p")" = chainsim ] && tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=0 &&
      rank0=$p
  done
  mpirun_pid=$(pgrep -P "$MPI_PID" | head -1)   # timeout's one child: mpirun (or mpiexec)
  [ -n "$rank0" ] && [ -n "$mpirun_pid" ] || { show "$err"; fail "no mpirun or rank 0 on host A"; }
  killed=$(ip netns pids "$P-c" | xargs -r ps -o comm= -p | sort | uniq -c | awk '{ printf "%s%s x%s", (NR > 1 ? ", " : ""), $2, $1 }')
  ip netns pids "$P-c" | xargs -r kill -9
  tk=$(date +%s.%N)
  path="" rank0_gone=""
  while [ -z "$path" ]; do
    if ! alive "$mpirun_pid"; then
      wait "$MPI_PID"
      rc=$?
      path=ended
    elif ! alive "$rank0"; then
      [ -n "$rank0_gone" ] || rank0_gone=$(date +%s.%N)
      awk -v a="$rank0_gone" -v b="$(date +%s.%N)" 'BEGIN { exit !(b - a > 10) }' && path=on
    fi
    awk -v a="$tk" -v b="$(date +%s.%N)" -v m="$RUN_TIMEOUT" 'BEGIN { exit !(b - a > m) }' &&
      { show "$err"; fail "neither mpirun nor rank 0 ended within $RUN_TIMEOUT s of host C's loss"; }
    sleep 0.1
  done
  took=$(elapsed "$tk")
  if [ $path = ended ]; then
    lost=$(key_on_c "$out") || lost=""
    if [ -n "$lost" ] && ! has_key "$out" "$lost"; then break; fi
  else
    named=$(grep "^optimize: rank 2 (pid [0-9]* on $HOST_C) sent nothing for $RANK_TIMEOUT s while evaluating; its evaluation of .* goes to another rank$" "$err")
    lost=$(sed -n 's/.* its evaluation of \(.*\) goes to another rank$/\1/p' <<<"$named" | head -1)
    # mpirun waits for the lost rank: interrupted as with Ctrl-C
    t_int=$(date +%s.%N)
    kill -INT "$mpirun_pid"
    for n in $(seq 150); do alive "$mpirun_pid" || break; sleep 0.1; done
    alive "$mpirun_pid" && { show "$err"; fail "mpirun did not end within 15 s of SIGINT"; }
    wait "$MPI_PID"
    rc=$?
    [ -n "$lost" ] && break
  fi
  log "3. attempt $attempt: host C held no unfinished evaluation when it was killed; again"
  lost=""
done
[ -n "$lost" ] || { show "$err"; fail "host C never died holding an evaluation"; }
log "3. host C killed ($killed)"
if [ $path = ended ]; then
  log "   OpenMPI ended the job: mpirun exit $rc after $took s"
  [ $rc != 0 ] || { show "$err"; fail "mpirun exited 0 after ending the job"; }
  awk -v s="$took" 'BEGIN { exit !(s < 60) }' || { show "$err"; fail "mpirun took $took s to end the job"; }
  grep -qE "ORTE was unable to reliably start one or more daemons|ORTE has lost communication with a remote daemon" "$err" ||
    { show "$err"; fail "OpenMPI did not say that it lost a daemon"; }
  grep -qF "netns_rsh: 10.77.0.3 (network namespace $P-c, host name $HOST_C): the remote command ended with" "$err" ||
    { show "$err"; fail "the launcher did not name host C"; }
  log "   $(grep -E 'ORTE was unable|ORTE has lost' "$err" | head -1)"
  log "   $(grep -F 'netns_rsh: 10.77.0.3' "$err" | head -1)"
  hosts_are_empty || fail "processes left after mpirun ended the job"
  before=$(journaled "$out")
  log "   journal: $before results; host C was evaluating: $lost"

  # the search continued on the hosts that are left
  t=$(date +%s.%N)
  : >"$T/launches.log"
  mpirun_on_a "$T/hosts-ab" 2 "$out" "$out-resume.txt" --resume
  wait "$MPI_PID"
  rc=$?
  [ $rc = 0 ] || { show "$out-resume.txt"; fail "mpirun --resume on A and B exited $rc"; }
  grep -q "1 MPI worker rank" "$out-resume.txt" || { show "$out-resume.txt"; fail "not 1 worker rank on resume"; }
  [ "$(awk '{ print $1 }' "$T/launches.log" | tr '\n' ' ')" = "10.77.0.2 " ] ||
    { cat "$T/launches.log"; fail "the resumed search did not run on host B only"; }
  has_key "$out" "$lost" || { show "$out-resume.txt"; fail "the evaluation lost with host C was not done again: $lost"; }
  history_of "$out" | diff "$T/reference.csv" - >&2 || { show "$out-resume.txt"; fail "history after --resume differs from the local one"; }
  hosts_are_empty || fail "processes left after the resumed search"
  log "   --resume on A and B: exit 0, journal $before -> $(journaled "$out") results (the lost evaluation among them), the local history; $(elapsed "$t") s"
else
  log "   OpenMPI went on with the job: $named"
  log "   rank 0 ended the search $(awk -v a="$tk" -v b="$rank0_gone" 'BEGIN { printf "%.1f", b - a }') s after the kill; mpirun still waited 10 s later; SIGINT: it exited $rc after $(elapsed "$t_int") s"
  grep -qE "ORTE was unable to reliably start one or more daemons|ORTE has lost communication with a remote daemon" "$err" &&
    log "   (mpirun had said: $(grep -E 'ORTE was unable|ORTE has lost' "$err" | head -1))"
  has_key "$out" "$lost" || { show "$err"; fail "the evaluation lost with host C was not done again: $lost"; }
  history_of "$out" | diff "$T/reference.csv" - >&2 || { show "$err"; fail "history after losing host C differs from the local one"; }
  hosts_are_empty || fail "processes left after mpirun was interrupted"
  log "   the lost evaluation done by rank 1 in the same job; the local history"
fi

cleanup
left=$(ip netns list | grep -F "$P-")
[ -z "$left" ] || fail "namespaces left: $left"
log "PASSED"

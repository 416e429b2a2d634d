#!/usr/bin/env bash
# `photoscene batch --slurm` against a real Slurm: a one-node cluster on 127.0.0.1 in a temporary
# folder (munged, slurmctld, slurmd on private ports and files), a batch of three scenes (one of
# them invalid), a task cancelled midway (scancel) and its resubmission finishing it.
#
#   tests/slurm/test_slurm_batch.sh PHOTOSCENE_BIN [PS_CACHE_DIR]
#
# Installs slurm-wlm and munge from Debian when missing (as root). Exit 77 (ctest: skipped) only
# when Slurm cannot be installed or a daemon cannot start on this machine; every daemon started
# here is stopped by its pid on exit.
set -uo pipefail

BIN=${1:?usage: $0 PHOTOSCENE_BIN [PS_CACHE_DIR]}
export PS_CACHE_DIR=${2:-${PS_CACHE_DIR:-}}
[ -n "$PS_CACHE_DIR" ] || unset PS_CACHE_DIR
BIN=$(readlink -f "$BIN")

skip() { echo "SKIP: $*"; exit 77; }
fail() {
  echo "FAIL: $*"
  for f in "$T"/slurmctld.log "$T"/slurmd.log; do [ -f "$f" ] && { echo "--- tail $f"; tail -n 20 "$f"; }; done
  exit 1
}
step() { echo "== $* ($(date +%T))"; }

# --- Slurm and munge ---------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null ||
  ! command -v sbatch >/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    step "installing slurm-wlm and munge"
    DEBIAN_FRONTEND=noninteractive timeout 600 apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null ||
      { apt-get update -qq >/dev/null && DEBIAN_FRONTEND=noninteractive timeout 600 apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null; } ||
      skip "slurm-wlm and munge are not installed and apt-get could not install them"
  else
    skip "slurm-wlm and munge are not installed (install them as root: apt-get install slurm-wlm munge)"
  fi
fi
[ "$(id -u)" = 0 ] || skip "the one-node cluster runs its daemons as root (SlurmUser=root); run as root"

T=$(mktemp -d /tmp/ps-slurm-XXXXXX)
chmod 755 "$T"
PIDS=()
cleanup() {
  # jobs first, while slurmd still runs their steps; then the daemons, each by the pid started here
  local p
  if [ -n "${SLURM_CONF:-}" ] && [ ${#PIDS[@]} -ge 3 ]; then
    timeout 10 scancel --full -u root >/dev/null 2>&1
    for _ in $(seq 60); do [ -z "$(timeout 5 squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.5; done
  fi
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for _ in $(seq 50); do
    local alive=0
    for p in "${PIDS[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    [ $alive = 0 ] && break
    sleep 0.2
  done
  for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null; done
  # a job step left behind (slurmd gone first) is a slurmstepd writing into this folder
  local d
  for d in /proc/[0-9]*; do
    case "$(tr '\0' ' ' <"$d/cmdline" 2>/dev/null)" in slurmstepd*) ;; *) continue ;; esac
    if ls -l "$d/fd" 2>/dev/null | grep -q -- "-> $T/"; then kill -KILL "${d#/proc/}" 2>/dev/null; fi
  done
  [ -n "${KEEP_TMP:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])' 2>/dev/null ||
  echo $((20000 + RANDOM % 20000)); }
# wait_for SECONDS COMMAND...: polls COMMAND every 0.5 s until it succeeds
wait_for() {
  local limit=$1; shift
  local end=$((SECONDS + limit))
  until "$@" >/dev/null 2>&1; do
    [ $SECONDS -ge $end ] && return 1
    sleep 0.5
  done
}

step "munged"
mkdir -p "$T/munge" "$T/state" "$T/spool"
chmod 700 "$T/munge"
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge/munge.key"
SOCK="$T/munge/munge.socket"
munged -F --force --key-file="$T/munge/munge.key" --socket="$SOCK" --pid-file="$T/munge/munged.pid" \
  --log-file="$T/munge/munged.log" --seed-file="$T/munge/munged.seed" >"$T/munge/stdout.log" 2>&1 &
PIDS+=($!)
wait_for 10 test -S "$SOCK" || skip "munged did not start: $(tail -n 5 "$T/munge/munged.log" "$T/munge/stdout.log" 2>/dev/null)"
munge -S "$SOCK" -n | unmunge -S "$SOCK" >/dev/null 2>&1 || skip "munged does not answer on $SOCK"

step "slurmctld and slurmd"
HOST=$(hostname -s)
CPUS=$(nproc)
MEM=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)
CTL_PORT=$(free_port)
D_PORT=$(free_port)
while [ "$D_PORT" = "$CTL_PORT" ]; do D_PORT=$(free_port); done
export SLURM_CONF="$T/slurm.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=pstest
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTL_PORT
SlurmdPort=$D_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCK
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
KillWait=30
InactiveLimit=0
MinJobAge=300
NodeName=pstest-node NodeAddr=127.0.0.1 NodeHostname=$HOST CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=pstest Nodes=pstest-node Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -c -f "$SLURM_CONF" >"$T/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -f "$SLURM_CONF" -N pstest-node >"$T/slurmd.out" 2>&1 &
PIDS+=($!)
node_idle() { sinfo -h -N -o %t 2>/dev/null | grep -qx idle; }
if ! wait_for 45 node_idle; then
  echo "--- slurmctld"; tail -n 15 "$T/slurmctld.log" "$T/slurmctld.out" 2>/dev/null
  echo "--- slurmd"; tail -n 15 "$T/slurmd.log" "$T/slurmd.out" 2>/dev/null
  skip "slurmctld / slurmd did not bring up an idle node in 45 s on this machine"
fi

# --- three small scenes, one invalid -----------------------------------------------------------
step "scenes"
make_scene() {  # make_scene DIR: a 4 x 2.5 x 3 m room seen by one 32 x 24 photo, walls labelled
  local d=$1
  mkdir -p "$d"
  cat >"$d/room.obj" <<'EOF'
v -2 0 -1.5
v 2 0 -1.5
v 2 0 1.5
v -2 0 1.5
v -2 2.5 -1.5
v 2 2.5 -1.5
v 2 2.5 1.5
v -2 2.5 1.5
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl floor
f 4/1 3/2 2/3 1/4
usemtl walls
f 1/1 2/2 6/3 5/4
f 2/1 3/2 7/3 6/4
usemtl ceiling
f 5/1 6/2 7/3 8/4
EOF
  oiiotool --create 32x24 3 --fill:color=0.55,0.45,0.35 0,0,32,24 -d uint8 -o "$d/photo.png" >/dev/null || return 1
  # label 7 everywhere (7 / 65535 as a 16-bit value)
  oiiotool --create 32x24 1 --fill:color=0.00010681315 0,0,32,24 -d uint16 -o "$d/labels.png" >/dev/null || return 1
  cat >"$d/scene.json" <<'EOF'
{"version": 1, "geometry": "room.obj",
 "views": [{"image": "photo.png", "segments": "labels.png", "segment_parts": {"7": "walls"},
   "camera": {"width": 32, "height": 24, "fx": 25, "fy": 25, "cx": 15.5, "cy": 11.5,
     "world_to_camera": [[1, 0, 0, 0], [0, -1, 0, 1.25], [0, 0, -1, 1.4], [0, 0, 0, 1]]}}],
 "parts": {"ceiling": {"skip": true}}}
EOF
}
S="$T/scenes"
make_scene "$S/room-a" && make_scene "$S/room-b" && make_scene "$S/room-c" || fail "cannot write the test scenes (oiiotool)"
mkdir -p "$S/broken"
echo '{"version": 1, "geometry": 5, "views": []}' >"$S/broken/scene.json"
printf '# three rooms, one of them invalid\nroom-a/scene.json\nbroken/scene.json  # geometry is a number\nroom-b/scene.json\n' >"$S/rooms.txt"

RUN_OPTS=(--preset fast --texture-size 16 --cpus-per-task 1 --mem 1G)

# --- 1. the batch: two done, one bad input ------------------------------------------------------
step "batch of three scenes (sbatch --wait)"
R1="$T/out1"
timeout 240 "$BIN" -q batch "$S/rooms.txt" -o "$R1" --slurm --wait "${RUN_OPTS[@]}" >"$T/batch1.out" 2>&1
rc=$?
cat "$T/batch1.out"
[ $rc = 2 ] || fail "batch exit status $rc, expected 2 (one scene with bad input, the others done)"
grep -q -- '--array=0-2' "$R1/.batch/job.sh" || fail "job.sh has no --array=0-2: $(grep SBATCH "$R1/.batch/job.sh")"
grep -q -- '--cpus-per-task=1' "$R1/.batch/job.sh" || fail "job.sh lacks --cpus-per-task=1"
[ "$(wc -l <"$R1/summary.csv")" = 4 ] || fail "summary.csv: expected a header and 3 rows: $(cat "$R1/summary.csv")"
head -1 "$R1/summary.csv" | grep -q '^name,status,exit_code,seconds' || fail "summary.csv header: $(head -1 "$R1/summary.csv")"
grep -q '^room-a,done,0,' "$R1/summary.csv" || fail "room-a not done: $(cat "$R1/summary.csv")"
grep -q '^room-b,done,0,' "$R1/summary.csv" || fail "room-b not done: $(cat "$R1/summary.csv")"
grep -q '^broken,bad-input,2,.*geometry' "$R1/summary.csv" || fail "broken not bad-input with its key: $(cat "$R1/summary.csv")"
for r in room-a room-b; do
  for f in metrics.json lights.json report.html materials/walls.json; do
    [ -s "$R1/$r/$f" ] || fail "$r/$f missing"
  done
  grep -q "href=\"$r/report.html\"" "$R1/index.html" || fail "index.html does not link $r/report.html"
done
[ ! -e "$R1/broken" ] || fail "a bad scene left an output folder behind"
ls "$R1"/.batch/slurm/*_0.out >/dev/null 2>&1 || fail "no Slurm task log in $R1/.batch/slurm"
"$BIN" -q batch --status "$R1" >"$T/status1.out" 2>&1
rc=$?
cat "$T/status1.out"
[ $rc = 2 ] || fail "--status exit $rc, expected 2"
grep -q 'broken .*bad-input .*geometry' "$T/status1.out" || fail "--status does not show the bad input with its error"

# --- 2. a task cancelled midway, then resubmitted -----------------------------------------------
step "a task cancelled at its fit stage, then resubmitted"
printf 'room-c/scene.json\n' >"$S/one.txt"
R2="$T/out2"
export PS_PAUSE_AT_STAGE=fit PS_PAUSE_MARKER="$T/paused"
timeout 60 "$BIN" -q batch "$S/one.txt" -o "$R2" --slurm "${RUN_OPTS[@]}" >"$T/submit2.out" 2>&1 ||
  fail "submission failed: $(cat "$T/submit2.out")"
unset PS_PAUSE_AT_STAGE PS_PAUSE_MARKER
cat "$T/submit2.out"
JOB=$(sed -n 's/^submitted Slurm job \([0-9]*\).*/\1/p' "$T/submit2.out")
[ -n "$JOB" ] || fail "no job id in: $(cat "$T/submit2.out")"
wait_for 120 test -f "$T/paused" || fail "the task did not reach its fit stage in 120 s"
"$BIN" -q batch --status "$R2" >"$T/status2.out" 2>&1
grep -q 'room-c .*running' "$T/status2.out" ||
  fail "--status does not show the task running: $(cat "$T/status2.out")"
scancel "${JOB}_0" || fail "scancel ${JOB}_0 failed"
job_gone() { [ -z "$(squeue -h -j "$JOB" -o %i 2>/dev/null)" ]; }
wait_for 90 job_gone || fail "job $JOB still in the queue 90 s after scancel"
"$BIN" -q batch --status "$R2" >"$T/status3.out" 2>&1
rc=$?
cat "$T/status3.out"
[ $rc = 1 ] || fail "--status after the cancel: exit $rc, expected 1 (pending)"
grep -q 'room-c .*pending .*interrupted' "$T/status3.out" || fail "the cancelled scene is not pending (interrupted)"
if find "$R2" -name '*.tmp-*' | grep -q .; then fail "temporary files left behind: $(find "$R2" -name '*.tmp-*')"; fi
ls "$R2"/room-c/.cache/align-* >/dev/null 2>&1 || fail "no cached align stage after the cancel"
[ ! -e "$R2/room-c/metrics.json" ] || fail "metrics.json written by a run cancelled before its fit"

timeout 240 "$BIN" -q batch "$S/one.txt" -o "$R2" --slurm --wait "${RUN_OPTS[@]}" >"$T/batch2.out" 2>&1
rc=$?
cat "$T/batch2.out"
[ $rc = 0 ] || fail "the resubmission exited $rc, expected 0"
grep -q '^room-c,done,0,' "$R2/summary.csv" || fail "room-c not done after the resubmission: $(cat "$R2/summary.csv")"
# the second attempt loaded the stages before the fit from the cache: geometry 0 computed, 1 cached
LOG="$R2/.batch/logs/room-c.log"
grep -q 'attempt 2' "$LOG" || fail "the log has no second attempt"
sed -n '/attempt 2/,$p' "$LOG" | grep -Eq '^geometry +[0-9.]+ +0 +1 ' ||
  fail "the resubmission recomputed the geometry stage: $(sed -n '/attempt 2/,$p' "$LOG" | grep -E '^(stage|geometry|align)')"

# --- 3. rerun: nothing left to submit -----------------------------------------------------------
step "rerun of a finished batch"
timeout 60 "$BIN" -q batch "$S/one.txt" -o "$R2" --slurm "${RUN_OPTS[@]}" >"$T/batch3.out" 2>&1
rc=$?
[ $rc = 0 ] || fail "rerun of a finished batch exited $rc: $(cat "$T/batch3.out")"
if grep -q '^submitted' "$T/batch3.out"; then fail "a finished batch was submitted again"; fi
[ "$(wc -l <"$R2/.batch/slurm/jobs.txt")" = 2 ] || fail "expected two submissions in jobs.txt"

echo "PASS: Slurm batch (two scenes done, one bad input; a cancelled task resumed from its stage cache)"
exit 0

#!/usr/bin/env bash
# End-to-end test of scripts/slurm-atlas.sh on a throwaway single-node Slurm
# cluster started on this machine (Debian's slurmctld + slurmd + munge).
#
#   scripts/test-slurm.sh            # as root; about 1-3 minutes
#
# It installs slurmctld, slurmd, slurm-client and munge with apt-get if they are
# missing, starts a private munged, slurmctld and slurmd (their key, socket,
# config, state, spool and logs all under $SLURM_TEST_DIR, default
# /tmp/vibroatlas-slurm-test; nothing under /etc is written), then:
#   A. submits a small atlas in 4 shards, waits for the array and the merge, and
#      compares the merged file bit for bit with a single-process run of the
#      same grid (scripts/compare_atlases.py); reruns one finished shard (a no-op),
#      deletes one part and resubmits the whole run (only that shard computes);
#   B. submits a larger atlas, cancels one shard while it runs, checks that the
#      merge is cancelled (not left pending) and that the shard's journal is
#      kept, reruns that shard alone (--rerun K: it resumes from the journal),
#      checks the new merge, merges once more with --merge-only, and compares
#      both with a single-process run.
# It stops the daemons it started on exit. Where the daemons cannot be started
# (not root, no packages, a Slurm already running here) it prints
# "test-slurm: SKIPPED: <reason>" and exits 0. Exit 1 if any check failed.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
W=${SLURM_TEST_DIR:-${TMPDIR:-/tmp}/vibroatlas-slurm-test}
BIN=${VIBROATLAS_BIN:-$repo/target/release/vibroatlas}
PY=${PYTHON:-/usr/bin/python3}
SLURM_ATLAS=$repo/scripts/slurm-atlas.sh
WAIT_S=${SLURM_TEST_WAIT_S:-180} # longest wait for one batch of jobs
T0=$SECONDS

say() { echo "test-slurm: $*"; }
checks=0 failures=0
pass() { checks=$((checks + 1)); say "PASS: $*"; }
fail() { checks=$((checks + 1)) failures=$((failures + 1)); say "FAIL: $*"; }
skip() { say "SKIPPED: $*"; exit 0; }
fatal() { fail "$*"; [[ ! -f $W/.vibroatlas-slurm-test ]] || say "work folder kept for inspection: $W"; exit 1; }
elapsed() { echo "$((SECONDS - $1))s"; }

# ---- daemons are stopped on every exit ------------------------------------------
started_pids=()
cleanup() {
    local rc=$?
    if ((${#started_pids[@]})); then
        if [[ -n ${SLURM_CONF:-} ]] && command -v scancel >/dev/null; then
            scancel --user="$(id -un)" >/dev/null 2>&1 || true
            sleep 1
        fi
        local i pid
        for ((i = ${#started_pids[@]} - 1; i >= 0; i--)); do # slurmd, slurmctld, then munged
            pid=${started_pids[i]}
            kill -TERM "$pid" 2>/dev/null || continue
            for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
            kill -KILL "$pid" 2>/dev/null || true
        done
        wait 2>/dev/null || true
        say "stopped the daemons it started (pids ${started_pids[*]})"
    fi
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# ---- preconditions ---------------------------------------------------------------
[[ -x $BIN ]] || fatal "no vibroatlas binary at $BIN (build it first: cargo build --release)"
[[ $(id -u) == 0 ]] || skip "needs root to install and start munged, slurmctld and slurmd (run it as root in a throwaway VM or container)"
"$PY" -c 'import h5py, numpy' 2>/dev/null || skip "$PY cannot import h5py and numpy, which scripts/compare_atlases.py needs"

tools=(slurmctld slurmd sbatch sinfo squeue scontrol scancel munged munge unmunge)
missing_tools() { local t; for t in "${tools[@]}"; do command -v "$t" >/dev/null 2>&1 || echo "$t"; done; }
if [[ -n $(missing_tools) ]]; then
    command -v apt-get >/dev/null || skip "Slurm/munge are not installed ($(missing_tools | paste -sd' ')) and there is no apt-get"
    say "installing slurmctld slurmd slurm-client munge with apt-get (missing: $(missing_tools | paste -sd' '))"
    t=$SECONDS
    if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurmctld slurmd slurm-client munge; } >/tmp/test-slurm-apt.log 2>&1; then
        tail -n 5 /tmp/test-slurm-apt.log | sed 's/^/    /'
        skip "apt-get could not install slurmctld slurmd slurm-client munge (log: /tmp/test-slurm-apt.log)"
    fi
    say "installed in $(elapsed "$t")"
    [[ -z $(missing_tools) ]] || skip "still missing after apt-get: $(missing_tools | paste -sd' ')"
fi
for d in slurmctld slurmd; do
    if pgrep -x "$d" >/dev/null; then
        skip "a $d already runs on this host (pid $(pgrep -x "$d" | paste -sd,)); this test starts its own cluster and will not touch that one"
    fi
done

# ---- work folder ------------------------------------------------------------------
if [[ -e $W ]]; then
    [[ -f $W/.vibroatlas-slurm-test ]] || fatal "$W exists and was not made by this test; set SLURM_TEST_DIR to another folder"
    rm -rf -- "$W"
fi
mkdir -p "$W"/{etc,state,spool,log,run,munge}
touch "$W/.vibroatlas-slurm-test"
chmod 755 "$W" "$W/run" # munged wants its socket folder reachable by all
chmod 700 "$W/munge"
say "work folder $W"

# ---- munged (private key and socket) ----------------------------------------------
if command -v mungekey >/dev/null; then
    mungekey --create --keyfile="$W/munge/munge.key" >/dev/null 2>&1
else
    dd if=/dev/urandom of="$W/munge/munge.key" bs=1024 count=1 status=none
fi
chmod 600 "$W/munge/munge.key"
SOCK=$W/run/munge.socket
munged --foreground --key-file="$W/munge/munge.key" --socket="$SOCK" --pid-file="$W/run/munged.pid" \
    --log-file="$W/log/munged.log" --seed-file="$W/munge/munged.seed" >"$W/log/munged.out" 2>&1 &
started_pids+=($!)
for _ in $(seq 50); do [[ -S $SOCK ]] && break; sleep 0.2; done
if ! munge -S "$SOCK" -n 2>/dev/null | unmunge -S "$SOCK" >/dev/null 2>&1; then
    tail -n 5 "$W/log/munged.out" | sed 's/^/    /'
    skip "munged did not start (log: $W/log/munged.out)"
fi
say "munged up (pid ${started_pids[0]})"

# ---- slurm.conf and the two Slurm daemons ---------------------------------------
HOST=$(hostname -s)
NCPU=$(nproc)
export SLURM_CONF=$W/etc/slurm.conf
cat >"$SLURM_CONF" <<EOF
# Single-node test cluster written by scripts/test-slurm.sh
ClusterName=vibroatlas-test
SlurmctldHost=$HOST(127.0.0.1)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCK
SlurmUser=root
SlurmdUser=root
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/run/slurmctld.pid
SlurmdPidFile=$W/run/slurmd.pid
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MinJobAge=900
KillWait=5
SlurmdParameters=config_overrides
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$NCPU State=UNKNOWN
PartitionName=debug Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
t=$SECONDS
slurmctld -D -i -f "$SLURM_CONF" >"$W/log/slurmctld.out" 2>&1 &
started_pids+=($!)
sleep 1
slurmd -D -f "$SLURM_CONF" >"$W/log/slurmd.out" 2>&1 &
started_pids+=($!)
state=""
for i in $(seq 120); do
    state=$(sinfo -h -N -n "$HOST" -o %T 2>/dev/null | head -n1) || true
    [[ $state == idle ]] && break
    for pid in "${started_pids[@]}"; do
        kill -0 "$pid" 2>/dev/null || {
            tail -n 5 "$W"/log/slurm*.out | sed 's/^/    /'
            skip "a Slurm daemon exited at start (logs: $W/log/)"
        }
    done
    if ((i % 20 == 0)) && [[ $state == down* || $state == drain* ]]; then
        scontrol update nodename="$HOST" state=resume 2>/dev/null || true
    fi
    sleep 0.5
done
if [[ $state != idle ]]; then
    tail -n 5 "$W"/log/slurmctld.log "$W"/log/slurmd.log 2>/dev/null | sed 's/^/    /'
    skip "the node did not become idle within 60 s (state '${state:-none}'; logs: $W/log/)"
fi
say "slurmctld and slurmd up in $(elapsed "$t"): $(sinfo -h -o '%P %a %D %T %N %c' | head -n1) (partition avail nodes state nodelist cpus)"

# ---- helpers -----------------------------------------------------------------------
# wait_jobs ID...: until none of them is pending, running or completing
wait_jobs() {
    local ids end=$((SECONDS + WAIT_S))
    ids=$(IFS=,; echo "$*")
    while squeue -h -j "$ids" 2>/dev/null | grep -q .; do
        if ((SECONDS > end)); then
            squeue -j "$ids" | sed 's/^/    /'
            fatal "jobs $ids not finished after $WAIT_S s"
        fi
        sleep 0.5
    done
}
# states ID: the states of a job (all tasks of an array), e.g. "4 COMPLETED"
states() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort | uniq -c | awk '{printf "%s%d %s", (NR>1?", ":""), $1, $2}'; }
reason() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\) Reason=\([^ ]*\).*/\1 (\2)/p' | head -n1; }
all_completed() { local s; s=$(states "$1"); [[ -n $s && $s != *,* && $s == *" COMPLETED" ]]; }
# submit ARGS...: runs slurm-atlas.sh, shows its output, sets ARRAY_ID and MERGE_ID
submit() {
    local outp
    if ! outp=$("$SLURM_ATLAS" "$@" 2>&1); then
        echo "$outp" | sed 's/^/    | /'
        fatal "scripts/slurm-atlas.sh $* failed"
    fi
    echo "$outp" | sed 's/^/    | /'
    ARRAY_ID=$(sed -n 's/^jobs: array=\([0-9a-z]*\) merge=\([0-9]*\)$/\1/p' <<<"$outp")
    MERGE_ID=$(sed -n 's/^jobs: array=\([0-9a-z]*\) merge=\([0-9]*\)$/\2/p' <<<"$outp")
    [[ -n $MERGE_ID ]] || fatal "no job ids in the output of slurm-atlas.sh"
}
compare() { # A B what
    local o
    if o=$("$PY" "$repo/scripts/compare_atlases.py" "$1" "$2" 2>&1); then
        pass "$3: bit-identical to the single-process run ($(tail -n1 <<<"$o"))"
    else
        sed 's/^/    /' <<<"$o" | head -n 20
        fail "$3: differs from the single-process run"
    fi
}
show_log_tail() { [[ -f $1 ]] && tail -n "${2:-3}" "$1" | sed 's/^/    > /'; }

cd "$repo"

# ---- A: a small atlas in 4 shards -------------------------------------------------
ARGS_A=(configs/multi-stop.toml --x omega=0.2:2.5:24 --y delta=0.1:1.5:12 --sweep both)
RA=$W/run-A
say "A: submit ${ARGS_A[*]} --shards 4"
t=$SECONDS
submit "${ARGS_A[@]}" --shards 4 --out "$RA"
A_ARRAY=$ARRAY_ID A_MERGE=$MERGE_ID
wait_jobs "$A_ARRAY" "$A_MERGE"
say "A: array $A_ARRAY: $(states "$A_ARRAY"); merge $A_MERGE: $(states "$A_MERGE"); submit to merged: $(elapsed "$t")"
if all_completed "$A_ARRAY" && all_completed "$A_MERGE" && [[ -f $RA/atlas.h5 ]]; then
    pass "A: 4 shards and the merge completed, $RA/atlas.h5 written"
else
    for f in "$RA"/logs/*.log; do echo "    $f:"; show_log_tail "$f" 4; done
    fatal "A: the jobs did not all complete"
fi
for k in 1 2 3 4; do
    s=$("$RA/vibroatlas" inspect "$RA/part-$k-of-4.h5" --json | "$PY" -c 'import json,sys; print(json.load(sys.stdin)["shard"])')
    [[ $s == "$k/4" ]] || fail "A: part-$k-of-4.h5 says shard $s"
done
t=$SECONDS
"$RA/vibroatlas" atlas "${ARGS_A[@]}" --threads "$NCPU" --quiet -o "$W/single-A.h5"
say "A: single-process run of the same grid: $(elapsed "$t")"
compare "$RA/atlas.h5" "$W/single-A.h5" "A: merged atlas"

sum_before=$(md5sum <"$RA/part-2-of-4.h5")
say "A: rerun finished shard 2 (must be a no-op)"
submit --out "$RA" --rerun 2
wait_jobs "$ARRAY_ID" "$MERGE_ID"
if [[ $(md5sum <"$RA/part-2-of-4.h5") == "$sum_before" ]] && grep -q 'already finished' "$RA/logs/shard-${ARRAY_ID}_2.log" &&
    all_completed "$ARRAY_ID" && all_completed "$MERGE_ID"; then
    pass "A: --rerun 2 of a finished part kept it byte for byte ($(tail -n1 "$RA/logs/shard-${ARRAY_ID}_2.log" | cut -c1-60)...), merge $MERGE_ID completed"
else
    show_log_tail "$RA/logs/shard-${ARRAY_ID}_2.log"
    fail "A: --rerun 2 of a finished part was not a no-op"
fi
compare "$RA/atlas.h5" "$W/single-A.h5" "A: atlas merged again after the no-op rerun"

say "A: delete part-3-of-4.h5, resubmit the original command with the same --out"
rm -f "$RA/part-3-of-4.h5"
submit "${ARGS_A[@]}" --shards 4 --out "$RA"
wait_jobs "$ARRAY_ID" "$MERGE_ID"
computed=$(grep -l '^shard [0-9]/4: wrote' "$RA"/logs/shard-"${ARRAY_ID}"_*.log 2>/dev/null | sed 's/.*_\([0-9]*\)\.log/\1/' | paste -sd,)
kept=$(grep -l 'already finished' "$RA"/logs/shard-"${ARRAY_ID}"_*.log 2>/dev/null | sed 's/.*_\([0-9]*\)\.log/\1/' | paste -sd,)
if all_completed "$ARRAY_ID" && all_completed "$MERGE_ID" && [[ $computed == 3 && $kept == 1,2,4 ]]; then
    pass "A: resubmission computed only shard 3 (kept 1,2,4); merge $MERGE_ID completed"
else
    fail "A: resubmission computed shards '$computed', kept '$kept' (expected 3 and 1,2,4); array $(states "$ARRAY_ID"), merge $(states "$MERGE_ID")"
fi
compare "$RA/atlas.h5" "$W/single-A.h5" "A: atlas after the resubmission"

# ---- B: kill one shard while it runs, rerun it alone, merge again ---------------
ARGS_B=(configs/multi-stop.toml --x omega=0.2:2.5:240 --y delta=0.1:1.5:40 --sweep both)
RB=$W/run-B
say "B: submit ${ARGS_B[*]} --shards 4"
t=$SECONDS
submit "${ARGS_B[@]}" --shards 4 --out "$RB"
B_ARRAY=$ARRAY_ID B_MERGE=$MERGE_ID
killed=""
end=$((SECONDS + WAIT_S))
while [[ -z $killed ]] && squeue -h -j "$B_ARRAY" 2>/dev/null | grep -q .; do
    ((SECONDS < end)) || fatal "B: array $B_ARRAY still running after $WAIT_S s"
    for k in 1 2 3 4; do
        [[ -s $RB/.part-$k-of-4.h5.journal && ! -e $RB/part-$k-of-4.h5 ]] || continue
        [[ $(squeue -h -j "${B_ARRAY}_$k" -o %T 2>/dev/null) == RUNNING ]] || continue
        sleep 0.7 # let it compute a little more
        [[ ! -e $RB/part-$k-of-4.h5 ]] || continue
        scancel "${B_ARRAY}_$k"
        killed=$k
        say "B: cancelled task ${B_ARRAY}_$k (shard $k/4) while it ran, $(elapsed "$t") after submission; journal $(stat -c %s "$RB/.part-$k-of-4.h5.journal") bytes"
        break
    done
    sleep 0.1
done
[[ -n $killed ]] || fatal "B: could not catch a shard while it ran (all finished too fast)"
wait_jobs "$B_ARRAY" "$B_MERGE"
say "B: array $B_ARRAY: $(states "$B_ARRAY"); merge $B_MERGE: $(reason "$B_MERGE")"
[[ $(states "${B_ARRAY}_$killed") == "1 CANCELLED" ]] &&
    pass "B: shard $killed/4 was cancelled" || fail "B: task ${B_ARRAY}_$killed is $(states "${B_ARRAY}_$killed"), not CANCELLED"
if [[ $(reason "$B_MERGE") == "CANCELLED (DependencyNeverSatisfied)" ]]; then
    pass "B: the merge $B_MERGE was cancelled (DependencyNeverSatisfied), not left pending"
else
    fail "B: the merge $B_MERGE is $(reason "$B_MERGE"), expected CANCELLED (DependencyNeverSatisfied)"
fi
if [[ -e $RB/.part-$killed-of-4.h5.journal && ! -e $RB/part-$killed-of-4.h5 && ! -e $RB/atlas.h5 ]]; then
    pass "B: shard $killed left its journal and no part; no atlas.h5 was written"
else
    ls -la "$RB" | sed 's/^/    /'
    fail "B: unexpected files after the cancel"
fi

say "B: rerun shard $killed alone"
t=$SECONDS
submit --out "$RB" --rerun "$killed"
wait_jobs "$ARRAY_ID" "$MERGE_ID"
say "B: rerun array $ARRAY_ID: $(states "$ARRAY_ID"); merge $MERGE_ID: $(states "$MERGE_ID"); rerun to merged: $(elapsed "$t")"
log=$RB/logs/shard-${ARRAY_ID}_$killed.log
if all_completed "$ARRAY_ID" && all_completed "$MERGE_ID" && grep -q 'resuming the interrupted run' "$log"; then
    pass "B: --rerun $killed resumed from the journal and the new merge completed"
    grep -E '^(shard|progress)' "$log" | sed 's/^/    > /'
else
    show_log_tail "$log" 6
    show_log_tail "$RB/logs/merge-$MERGE_ID.log" 4
    fail "B: the rerun of shard $killed or its merge failed"
fi
t=$SECONDS
"$RB/vibroatlas" atlas "${ARGS_B[@]}" --threads "$NCPU" --quiet -o "$W/single-B.h5"
say "B: single-process run of the same grid: $(elapsed "$t")"
compare "$RB/atlas.h5" "$W/single-B.h5" "B: atlas after the killed shard was rerun"

say "B: merge again with --merge-only"
mv "$RB/atlas.h5" "$W/atlas-B-first.h5"
submit --out "$RB" --merge-only
wait_jobs "$MERGE_ID"
if all_completed "$MERGE_ID" && [[ -f $RB/atlas.h5 ]]; then
    pass "B: --merge-only job $MERGE_ID completed"
    compare "$RB/atlas.h5" "$W/single-B.h5" "B: atlas from --merge-only"
else
    show_log_tail "$RB/logs/merge-$MERGE_ID.log" 4
    fail "B: --merge-only job $MERGE_ID: $(states "$MERGE_ID")"
fi

# ---- summary --------------------------------------------------------------------------
say "jobs: $(squeue -h -t all -o '%i %T' 2>/dev/null | wc -l) in the controller; work folder $W (logs in run-*/logs, daemons' in log/)"
if ((failures)); then
    say "FAILED: $failures of $checks checks, $(elapsed "$T0")"
    exit 1
fi
say "ALL PASSED: $checks checks, $(elapsed "$T0")"

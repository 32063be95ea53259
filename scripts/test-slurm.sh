#!/usr/bin/env bash
# End-to-end test of scripts/slurm-atlas.sh on a throwaway single-node Slurm
# cluster started on this machine (Debian's slurmctld + slurmd + munge).
#
#   scripts/test-slurm.sh                          # as root; about 1-2 minutes
#   SLURM_TEST_REQUIRED=1 scripts/test-slurm.sh    # what .ci/run does: fail, never skip
#
# G (no Slurm needed): the pass-through grammar: everything after `--` reaches
#   `vibroatlas atlas` word for word (a scene path with a space, --attractors);
#   --shard, --threads, --resume and -o/--output there are refused.
# Then it installs slurmctld, slurmd, slurm-client and munge with apt-get if they
# are missing and starts a private munged, slurmctld and slurmd (key, socket,
# config, state, spool and logs under $SLURM_TEST_DIR, default
# /tmp/vibroatlas-slurm-test; nothing under /etc is written), and checks:
# A. an --attractors run in 3 shards (--wait): merged bit for bit the file of a
#    single-process run (scripts/compare_atlases.py); the same command again
#    after a part was deleted computes only that shard; a word after `--` that
#    atlas does not know fails the shards, cancels the merge, --wait exits 1;
# B. a shard cancelled while it runs: the merge is cancelled, the journal kept;
#    --rerun K resumes from the journal; the merge is bit for bit the
#    single-process run;
# C. --rerun of a finished shard: exit 0, the part unchanged (bytes and mtime),
#    in a fraction of the time the shard took to compute;
# D. a part missing: --merge-only fails and its log names the missing shard.
# It stops the daemons it started on exit. Where the daemons cannot be started
# (not root, no packages, a Slurm already running here) it prints
# "test-slurm: SKIPPED: <reason>" and exits 0, or, with SLURM_TEST_REQUIRED=1,
# "test-slurm: FAIL: ..." and exits 1. Exit 1 if any check failed.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
W=${SLURM_TEST_DIR:-${TMPDIR:-/tmp}/vibroatlas-slurm-test}
BIN=${VIBROATLAS_BIN:-$repo/target/release/vibroatlas}
export VIBROATLAS_BIN=$BIN
PY=${PYTHON:-/usr/bin/python3}
SLURM_ATLAS=$repo/scripts/slurm-atlas.sh
WAIT_S=${SLURM_TEST_WAIT_S:-240} # longest wait for one batch of jobs
T0=$SECONDS

say() { echo "test-slurm: $*"; }
checks=0 failures=0
pass() { checks=$((checks + 1)); say "PASS: $*"; }
fail() { checks=$((checks + 1)) failures=$((failures + 1)); say "FAIL: $*"; }
fatal() { fail "$*"; [[ ! -f $W/.vibroatlas-slurm-test ]] || say "work folder kept for inspection: $W"; exit 1; }
skip() {
    [[ ${SLURM_TEST_REQUIRED:-0} != 1 ]] || fatal "cannot run the Slurm test, and SLURM_TEST_REQUIRED=1: $*"
    say "SKIPPED: $*"
    exit 0
}
elapsed() { echo "$((SECONDS - $1))s"; }
indent() { sed "s/^/    ${1:-}/"; }

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

[[ -x $BIN ]] || fatal "no vibroatlas binary at $BIN (build it first: cargo build --release)"
"$PY" -c 'import h5py, numpy' 2>/dev/null || skip "$PY cannot import h5py and numpy, which scripts/compare_atlases.py needs"
if [[ -e $W ]]; then
    [[ -f $W/.vibroatlas-slurm-test ]] || fatal "$W exists and was not made by this test; set SLURM_TEST_DIR to another folder"
    rm -rf -- "$W"
fi
mkdir -p "$W"/{etc,state,spool,log,run,munge}
touch "$W/.vibroatlas-slurm-test"
chmod 755 "$W" "$W/run" # munged wants its socket folder reachable by all
chmod 700 "$W/munge"
say "work folder $W, binary $BIN ($("$BIN" --version))"
cd "$repo"

# ---- G: the grammar, without Slurm -------------------------------------------------
mkdir -p "$W/my scenes"
cp configs/multi-stop.toml "$W/my scenes/two masses.toml"
GRID_G=(--x omega=0.2:2.5:8 --y delta=0.1:1.5:4 --sweep both --attractors 12)
RG=$W/run-G
if o=$(cd "$W" && "$SLURM_ATLAS" --shards 2 --dry-run --out run-G -- "my scenes/two masses.toml" "${GRID_G[@]}" 2>&1) &&
    grep -qF -- '--attractors 12' "$RG/shard.sbatch" &&
    (cd /tmp && SLURM_ARRAY_TASK_ID=2 SLURM_CPUS_PER_TASK=1 bash "$RG/shard.sbatch" >"$W/g-shard2.log" 2>&1) &&
    "$BIN" inspect "$RG/part-2-of-2.h5" --json | "$PY" -c 'import json, sys; sys.exit(json.load(sys.stdin)["shard"] != "2/2")' &&
    "$PY" -c 'import h5py, sys; sys.exit(0 if "attractors" in h5py.File(sys.argv[1], "r") else 1)' "$RG/part-2-of-2.h5"; then
    pass "G: '--shards 2 --dry-run -- SCENE ... --attractors 12' wrote shard.sbatch; its task 2, started elsewhere, ran 'atlas' with every word (a relative scene path with spaces, --attractors 12) and wrote shard 2/2 with attractors"
else
    echo "$o" | indent '| '
    tail -n 5 "$W/g-shard2.log" 2>/dev/null | indent '> '
    fail "G: the pass-through of '-- SCENE ... --attractors 12' did not reach vibroatlas as given"
fi
refused=() accepted=()
for opt in "--threads 2" "--shard 1/2" "--resume" "-o x.h5" "--output=x.h5"; do
    rc=0
    # shellcheck disable=SC2086 # $opt is one or two words on purpose
    o=$("$SLURM_ATLAS" --shards 2 --dry-run --out "$W/run-refused" -- configs/multi-stop.toml "${GRID_G[@]}" $opt 2>&1) || rc=$?
    if [[ $rc == 2 && $(wc -l <<<"$o") == 1 && $o == *"set by this script"* && ! -e $W/run-refused ]]; then
        refused+=("$opt")
    else
        accepted+=("$opt (exit $rc: $o)")
    fi
done
if ((${#accepted[@]} == 0)); then
    pass "G: ${refused[*]} after '--' each refused with one error line, nothing written"
else
    fail "G: not refused cleanly after '--': ${accepted[*]}"
fi
if ! o=$("$SLURM_ATLAS" --shards 2 --dry-run --out "$W/run-refused" configs/multi-stop.toml "${GRID_G[@]}" 2>&1) && [[ $o == *"after '--'"* ]]; then
    pass "G: atlas options without '--' refused: $o"
else
    fail "G: atlas options without '--' not refused: $o"
fi
# Issue 42, R16: more shards than vibroatlas takes, and a folder of another run, in one line each.
rc=0
o=$("$SLURM_ATLAS" --shards 99999999999999999999 --dry-run --out "$W/run-refused" -- configs/multi-stop.toml "${GRID_G[@]}" 2>&1) || rc=$?
rc2=0
o2=$(cd "$W" && "$SLURM_ATLAS" --shards 3 --dry-run --out run-G -- "my scenes/two masses.toml" "${GRID_G[@]}" 2>&1) || rc2=$?
if [[ $rc == 2 && $(wc -l <<<"$o") == 1 && $o == *"at most 100000 shards"* && ! -e $W/run-refused &&
    $rc2 == 2 && $(wc -l <<<"$o2") == 1 && $o2 == *"holds another run"* ]]; then
    pass "G: --shards beyond 100000 and a folder of another run refused in one line each: $o | $o2"
else
    fail "G: not refused in one line: ($rc) $o | ($rc2) $o2"
fi

# ---- root, packages ----------------------------------------------------------------
[[ $(id -u) == 0 ]] || skip "needs root to install and start munged, slurmctld and slurmd (run it as root in a throwaway VM or container)"
tools=(slurmctld slurmd sbatch sinfo squeue scontrol scancel munged munge unmunge)
missing_tools() { local t; for t in "${tools[@]}"; do command -v "$t" >/dev/null 2>&1 || echo "$t"; done; }
if [[ -n $(missing_tools) ]]; then
    command -v apt-get >/dev/null || skip "Slurm/munge are not installed ($(missing_tools | paste -sd' ')) and there is no apt-get"
    say "installing slurmctld slurmd slurm-client munge with apt-get (missing: $(missing_tools | paste -sd' '))"
    t=$SECONDS
    if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurmctld slurmd slurm-client munge; } >"$W/log/apt.log" 2>&1; then
        tail -n 5 "$W/log/apt.log" | indent
        skip "apt-get could not install slurmctld slurmd slurm-client munge (log: $W/log/apt.log)"
    fi
    say "installed in $(elapsed "$t")"
    [[ -z $(missing_tools) ]] || skip "still missing after apt-get: $(missing_tools | paste -sd' ')"
fi
for d in slurmctld slurmd; do
    if pgrep -x "$d" >/dev/null; then
        skip "a $d already runs on this host (pid $(pgrep -x "$d" | paste -sd,)); this test starts its own cluster and will not touch that one"
    fi
done

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
            squeue -j "$ids" | indent
            fatal "jobs $ids not finished after $WAIT_S s"
        fi
        sleep 0.5
    done
}
# states ID: the states of a job (all tasks of an array), e.g. "4 COMPLETED"
states() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort | uniq -c | awk '{printf "%s%d %s", (NR>1?", ":""), $1, $2}'; }
reason() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\) Reason=\([^ ]*\).*/\1 (\2)/p' | head -n1; }
# slurm_atlas ARGS...: runs slurm-atlas.sh (with a time limit), shows its output,
# sets RC, ARRAY_ID and MERGE_ID
slurm_atlas() {
    local outp
    RC=0
    outp=$(timeout "$WAIT_S" "$SLURM_ATLAS" "$@" 2>&1) || RC=$?
    echo "$outp" | indent '| '
    ARRAY_ID=$(sed -n 's/^jobs: array=\([0-9a-z]*\) merge=\([0-9]*\)$/\1/p' <<<"$outp")
    MERGE_ID=$(sed -n 's/^jobs: array=\([0-9a-z]*\) merge=\([0-9]*\)$/\2/p' <<<"$outp")
    [[ -n $MERGE_ID ]] || fatal "no job ids in the output of slurm-atlas.sh $*"
}
compare() { # A B what
    local o
    if o=$("$PY" "$repo/scripts/compare_atlases.py" "$1" "$2" 2>&1); then
        pass "$3: bit-identical to the single-process run ($(tail -n1 <<<"$o"))"
    else
        indent <<<"$o" | head -n 20
        fail "$3: differs from the single-process run"
    fi
}
single() { # file atlas-args...: the same grid in one process
    local f=$1 t=$SECONDS
    shift
    "$BIN" atlas "$@" --threads "$NCPU" --quiet -o "$f"
    say "single-process run of the same grid: $(elapsed "$t")"
}
took() { sed -n 's/^shard [0-9]*\/[0-9]*: vibroatlas exited 0 after \([0-9.]*\) s$/\1/p' "$1" | tail -n1; }

# ---- A: an --attractors run in 3 shards ----------------------------------------------
ARGS_A=(configs/multi-stop.toml --x omega=0.2:2.5:24 --y delta=0.1:1.5:12 --sweep both --attractors 8)
RA=$W/run-A
rc=0
o=$("$SLURM_ATLAS" --shards 2 --cpus $((NCPU + 1)) --out "$W/run-refused" -- "${ARGS_A[@]}" 2>&1) || rc=$?
rc2=0
o2=$("$SLURM_ATLAS" --shards 2 --partition no-such-partition --out "$W/run-refused" -- "${ARGS_A[@]}" 2>&1) || rc2=$?
if [[ $rc == 2 && $rc2 == 2 && ! -e $W/run-refused ]]; then
    pass "A: refused before writing anything: --cpus $((NCPU + 1)) ($o), an unknown partition ($o2)"
else
    fail "A: --cpus $((NCPU + 1)): exit $rc ($o); unknown partition: exit $rc2 ($o2)"
fi
say "A: slurm-atlas.sh --shards 3 --partition debug --cpus $NCPU --time 10 --wait -- ${ARGS_A[*]}"
t=$SECONDS
slurm_atlas --shards 3 --partition debug --cpus "$NCPU" --time 10 --out "$RA" --wait -- "${ARGS_A[@]}"
job=$(scontrol -o show job "${ARRAY_ID}_1" 2>/dev/null)
if ((RC == 0)) && [[ $(states "$ARRAY_ID") == "3 COMPLETED" && -f $RA/atlas.h5 ]] &&
    [[ $job == *" Partition=debug "* && $job == *" TimeLimit=00:10:00 "* && $job == *" NumCPUs=$NCPU "* ]]; then
    pass "A: 3 shards (partition debug, $NCPU CPUs, 10 min each) and the merge completed in $(elapsed "$t"), --wait exited 0"
else
    for f in "$RA"/logs/*.log; do echo "    $f:"; tail -n 4 "$f" | indent '> '; done
    fatal "A: --wait exited $RC; array $(states "$ARRAY_ID"), merge $(reason "$MERGE_ID")"
fi
single "$W/single-A.h5" "${ARGS_A[@]}"
compare "$RA/atlas.h5" "$W/single-A.h5" "A: merged --attractors 8 atlas"

say "A: part-2-of-3.h5 deleted; the original command submitted again with the same --out"
stamps() { for k in 1 3; do stat -c '%n %s %y' "$RA/part-$k-of-3.h5"; done; }
kept=$(stamps)
rm "$RA/part-2-of-3.h5"
slurm_atlas --shards 3 --out "$RA" --wait -- "${ARGS_A[@]}"
if ((RC == 0)) && [[ $(stamps) == "$kept" && -f $RA/part-2-of-3.h5 ]]; then
    pass "A: the resubmission computed shard 2 again and left parts 1 and 3 as they were; merge completed"
else
    for k in 1 2 3; do tail -n 2 "$RA/logs/shard-${ARRAY_ID}_$k.log" | indent '> '; done
    fail "A: the resubmission exited $RC, or touched a finished part"
fi
compare "$RA/atlas.h5" "$W/single-A.h5" "A: atlas after the resubmission"

say "A: a word after '--' that vibroatlas atlas does not know (--no-such-option), --wait"
slurm_atlas --shards 2 --out "$W/run-bad" --wait -- "${ARGS_A[@]}" --no-such-option
if ((RC == 1)) && [[ $(states "$ARRAY_ID") == "2 FAILED" && $(reason "$MERGE_ID") == "CANCELLED (DependencyNeverSatisfied)" ]] &&
    grep -q -- '--no-such-option' "$W/run-bad/logs/shard-${ARRAY_ID}_1.log"; then
    pass "A: both shards failed with vibroatlas's own error, the merge was cancelled, --wait exited 1"
else
    fail "A: with --no-such-option: --wait exited $RC, array $(states "$ARRAY_ID"), merge $(reason "$MERGE_ID")"
fi

# ---- B: a shard cancelled while it runs, then rerun ---------------------------------
ARGS_B=(configs/multi-stop.toml --x omega=0.2:2.5:240 --y delta=0.1:1.5:80 --sweep both)
RB=$W/run-B
say "B: slurm-atlas.sh --shards 4 -- ${ARGS_B[*]}"
t=$SECONDS
slurm_atlas --shards 4 --out "$RB" -- "${ARGS_B[@]}"
((RC == 0)) || fatal "B: slurm-atlas.sh exited $RC"
B_ARRAY=$ARRAY_ID B_MERGE=$MERGE_ID
killed=""
end=$((SECONDS + WAIT_S))
while [[ -z $killed ]] && squeue -h -j "$B_ARRAY" 2>/dev/null | grep -q .; do
    ((SECONDS < end)) || fatal "B: array $B_ARRAY still running after $WAIT_S s"
    for k in 1 2 3 4; do
        [[ -s $RB/.part-$k-of-4.h5.journal && ! -e $RB/part-$k-of-4.h5 ]] || continue
        [[ $(squeue -h -j "${B_ARRAY}_$k" -o %T 2>/dev/null) == RUNNING ]] || continue
        sleep 0.3 # let it compute a little more
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
if [[ $(states "${B_ARRAY}_$killed") == "1 CANCELLED" && $(reason "$B_MERGE") == "CANCELLED (DependencyNeverSatisfied)" ]]; then
    pass "B: shard $killed/4 cancelled; the merge $B_MERGE cancelled with it (DependencyNeverSatisfied), not left pending"
else
    fail "B: task ${B_ARRAY}_$killed is $(states "${B_ARRAY}_$killed"), merge $(reason "$B_MERGE"); expected CANCELLED, CANCELLED (DependencyNeverSatisfied)"
fi
if [[ -s $RB/.part-$killed-of-4.h5.journal && ! -e $RB/part-$killed-of-4.h5 && ! -e $RB/atlas.h5 ]]; then
    pass "B: shard $killed left its journal ($(stat -c %s "$RB/.part-$killed-of-4.h5.journal") bytes) and no part; no atlas.h5"
else
    ls -la "$RB" | indent
    fatal "B: unexpected files after the cancel"
fi

say "B: slurm-atlas.sh --out DIR --rerun $killed --wait"
t=$SECONDS
slurm_atlas --out "$RB" --rerun "$killed" --wait
log=$RB/logs/shard-${ARRAY_ID}_$killed.log
if ((RC == 0)) && grep -q 'journal is there' "$log" && [[ -f $RB/part-$killed-of-4.h5 && ! -e $RB/.part-$killed-of-4.h5.journal ]]; then
    pass "B: --rerun $killed resumed from the journal (exit 0, journal gone, part written), new merge completed, $(elapsed "$t")"
    grep -E '^(shard|progress)' "$log" | indent '> '
else
    tail -n 6 "$log" | indent '> '
    fail "B: --rerun $killed exited $RC, or did not resume from the journal"
fi
single "$W/single-B.h5" "${ARGS_B[@]}"
compare "$RB/atlas.h5" "$W/single-B.h5" "B: atlas after the cancelled shard was rerun"

# ---- C: a finished shard rerun is a no-op ----------------------------------------------
# The finished shard that took longest to compute (not the resumed one).
k_c="" x_c=0
for k in 1 2 3 4; do
    ((k != killed)) || continue
    s=$(took "$RB/logs/shard-${B_ARRAY}_$k.log")
    [[ -n $s ]] && awk -v a="$s" -v b="$x_c" 'BEGIN { exit !(a > b) }' && k_c=$k x_c=$s
done
[[ -n $k_c ]] || fatal "C: no 'vibroatlas exited 0 after S s' line in the shard logs of array $B_ARRAY"
part=$RB/part-$k_c-of-4.h5
before=$(stat -c '%s %y' "$part")$(md5sum <"$part")
say "C: slurm-atlas.sh --out DIR --rerun $k_c --wait (shard $k_c took $x_c s to compute)"
slurm_atlas --out "$RB" --rerun "$k_c" --wait
log=$RB/logs/shard-${ARRAY_ID}_$k_c.log
y_c=$(took "$log")
after=$(stat -c '%s %y' "$part")$(md5sum <"$part")
if ((RC == 0)) && [[ $after == "$before" && -n $y_c ]] && awk -v y="$y_c" -v x="$x_c" 'BEGIN { exit !(y < x / 2) }'; then
    pass "C: --rerun $k_c of the finished shard: exit 0, part unchanged (bytes and mtime), $y_c s against $x_c s to compute"
    grep -v '^progress' "$log" | indent '> '
else
    grep -v '^progress' "$log" | tail -n 6 | indent '> '
    [[ $after == "$before" ]] || say "C: part-$k_c-of-4.h5 was rewritten: before '$before', after '$after'"
    fail "C: --rerun $k_c of a finished shard was not a no-op (exit $RC, ${y_c:-?} s against $x_c s to compute)"
fi

# ---- D: a missing part: the merge names it -------------------------------------------------
k_d=$(((killed % 4) + 1))
mv "$RB/part-$k_d-of-4.h5" "$W/part-$k_d-of-4.h5.away"
say "D: part-$k_d-of-4.h5 moved away; slurm-atlas.sh --out DIR --merge-only --wait"
slurm_atlas --out "$RB" --merge-only --wait
log=$RB/logs/merge-$MERGE_ID.log
if ((RC != 0)) && [[ $(states "$MERGE_ID") == "1 FAILED" ]] && grep -E "shards? .*\b$k_d\b.*missing" "$log" >/dev/null; then
    pass "D: --merge-only without part $k_d failed (exit $RC) and its log names the shard: ...$(grep -E -o "shards? [^)]*\b$k_d\b[^)]*missing" "$log" | head -n1)..."
else
    tail -n 4 "$log" | indent '> '
    fail "D: --merge-only without part $k_d: exit $RC, merge $(states "$MERGE_ID"), or no line naming shard $k_d as missing"
fi
mv "$W/part-$k_d-of-4.h5.away" "$RB/part-$k_d-of-4.h5"

# ---- summary --------------------------------------------------------------------------------
say "jobs: $(squeue -h -t all -o '%i %T' 2>/dev/null | wc -l) in the controller; work folder $W (logs in run-*/logs, daemons' in log/)"
if ((failures)); then
    say "FAILED: $failures of $checks checks, $(elapsed "$T0")"
    exit 1
fi
say "ALL PASSED: $checks checks, $(elapsed "$T0")"

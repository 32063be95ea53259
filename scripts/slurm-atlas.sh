#!/usr/bin/env bash
# Runs `vibroatlas atlas` on Slurm: a job array of N shards, then a merge job
# that runs when every shard succeeded. Glue only: the atlas options go to
# vibroatlas unchanged, which resumes, skips and merges by itself. Run with --help.
set -euo pipefail

usage() {
    cat <<'EOF'
Usage:
  scripts/slurm-atlas.sh --shards N [OPTIONS] -- SCENE ATLAS-OPTIONS...
  scripts/slurm-atlas.sh --out DIR --rerun K[,K...] [--partition P] [--cpus C] [--time T] [--wait]
  scripts/slurm-atlas.sh --out DIR --merge-only [--allow-missing] [--partition P] [--time T] [--wait]

Computes `vibroatlas atlas SCENE ATLAS-OPTIONS...` as a Slurm job array of N
shards; shard K runs, in the folder this script was started from,

  DIR/vibroatlas atlas SCENE ATLAS-OPTIONS... --shard K/N --threads C --resume -o DIR/part-K-of-N.h5

which is safe to run again: a finished part is left as it is, an interrupted
one resumes from its journal. A merge job then runs
`vibroatlas merge DIR/part-*-of-N.h5 -o DIR/atlas.h5`, which fails naming the
shards that are missing. Everything after `--` goes to `vibroatlas atlas`
unchanged, except --shard, --threads, --resume and -o/--output, which this
script sets and refuses there.

  --shards N         number of shards (array tasks 1..N)
  --out DIR          run folder, on a file system the compute nodes see (default:
                     out/slurm-YYYYmmdd-HHMMSS). It receives a copy of the binary,
                     the batch scripts, logs/, the parts and atlas.h5.
  --name NAME        job name (default: the run folder's name)
  --partition P      Slurm partition (default: the cluster's default)
  --cpus C           CPUs per shard = --threads (default: the smallest node's CPU count)
  --time T           time limit of each job, as sbatch --time (default: the partition's)
  --bin PATH         vibroatlas binary (default: $VIBROATLAS_BIN, or target/release/vibroatlas)
  --rerun K[,K...]   resubmit these shards of the run in DIR, and a merge after them
  --merge-only       submit only the merge of the parts in DIR
  --allow-missing    with --merge-only: merge even with shards missing
  --wait             wait for the jobs; exit 0 only when atlas.h5 was written
  --dry-run          write DIR and the batch scripts, print the sbatch commands, submit nothing
  -h, --help         this text

Submitting the same command again with the same --out DIR reruns every shard:
finished ones exit at once, interrupted ones resume, missing ones compute.
EOF
}

prog=slurm-atlas
die() { echo "$prog: error: $*" >&2; exit 2; }
note() { echo "$prog: $*"; }
self=$(readlink -f -- "${BASH_SOURCE[0]}")
repo=$(dirname -- "$(dirname -- "$self")")

shards="" out="" name="" partition="" cpus="" time_limit="" rerun="" bin=${VIBROATLAS_BIN:-}
merge_only=0 allow_missing=0 wait=0 dry_run=0 atlas=()
while (($#)); do
    case $1 in
        -h | --help) usage; exit 0 ;;
        --shards | --out | --name | --partition | --cpus | --time | --rerun | --bin)
            [[ $# -ge 2 && -n $2 ]] || die "$1 needs a value"
            case $1 in
                --shards) shards=$2 ;; --out) out=$2 ;; --name) name=$2 ;; --partition) partition=$2 ;;
                --cpus) cpus=$2 ;; --time) time_limit=$2 ;; --rerun) rerun=$2 ;; --bin) bin=$2 ;;
            esac
            shift ;;
        --merge-only) merge_only=1 ;;
        --allow-missing) allow_missing=1 ;;
        --wait) wait=1 ;;
        --dry-run) dry_run=1 ;;
        --) shift; atlas=("$@"); break ;;
        *) die "unknown option '$1'; the scene and the atlas options go after '--' (see --help)" ;;
    esac
    shift
done
for a in "${atlas[@]}"; do
    case $a in
        --shard | --shard=* | --threads | --threads=* | --resume | -o | -o* | --output | --output=*)
            die "'${a%%=*}' is set by this script for each shard (--shard K/N --threads C --resume -o DIR/part-K-of-N.h5); leave it out after '--'" ;;
    esac
done
is_count() { [[ $1 =~ ^[1-9][0-9]*$ ]]; }
[[ -z $cpus ]] || is_count "$cpus" || die "--cpus must be a positive whole number, not '$cpus'"
q() { printf '%q' "$1"; }
words() { (($# == 0)) || printf '%q ' "$@"; }

mode=submit
[[ -n $rerun ]] && mode=rerun
if ((merge_only)); then
    [[ $mode == submit ]] || die "--rerun and --merge-only exclude each other"
    mode=merge
fi
((allow_missing == 0 || merge_only)) || die "--allow-missing goes with --merge-only"
if [[ $mode == submit ]]; then
    is_count "$shards" || die "--shards N (a positive whole number) is required"
    # vibroatlas takes --shard K/N up to N = 100000 (checked before bash's arithmetic overflows).
    ((${#shards} <= 6 && shards <= 100000)) || die "--shards: at most 100000 shards, not '$shards'"
    ((${#atlas[@]})) || die "nothing after '--': give the scene and the atlas options, e.g. -- configs/multi-stop.toml --x omega=0.1:3:60 --y delta=0.05:2:40"
    out=$(readlink -m -- "${out:-out/slurm-$(date +%Y%m%d-%H%M%S)}")
else
    [[ -n $out ]] || die "--rerun and --merge-only need --out DIR, the run's folder"
    [[ -z $shards && ${#atlas[@]} == 0 ]] || die "--rerun and --merge-only take the run's settings from DIR; leave out --shards and '-- ...'"
    out=$(readlink -m -- "$out")
    [[ -f $out/shard.sbatch && -f $out/merge.sbatch ]] || die "'$out' holds no run of this script"
    shards=$(sed -n 's/^SHARDS=//p' "$out/shard.sbatch")
    IFS=, read -r -a ks <<<"$rerun"
    for k in "${ks[@]}"; do
        is_count "$k" && ((k <= shards)) || die "--rerun: '$k' is not a shard of this run (1..$shards)"
    done
fi

# ---- the run folder: one run per folder, one binary per run ---------------------
# The run: folder it was submitted from, shard count, atlas words, one line.
run_line="cwd=$(q "$PWD") shards=$shards atlas: $(words "${atlas[@]}")"
if [[ $mode == submit ]]; then
    if [[ -f $out/run.txt ]]; then
        [[ $(<"$out/run.txt") == "$run_line" ]] ||
            die "'$out' holds another run ($(<"$out/run.txt")), not this one ($run_line); choose another --out"
    elif [[ -e $out && -n $(ls -A -- "$out" 2>/dev/null) ]]; then
        die "'$out' exists and holds no run of this script; choose another --out"
    fi
fi
if [[ ! -x $out/vibroatlas ]]; then
    bin=${bin:-$repo/target/release/vibroatlas}
    "$bin" --version >/dev/null 2>&1 || die "vibroatlas binary '$bin' does not run here (build it, or pass --bin)"
elif [[ -n $bin && $mode == submit ]]; then
    note "using the run's own binary $out/vibroatlas, not $bin"
fi

# ---- CPUs per shard (a count no node has would pend forever) ---------------------
have_slurm=1
command -v sbatch >/dev/null && command -v sinfo >/dev/null || have_slurm=0
((have_slurm || dry_run)) || die "sbatch/sinfo not found (--dry-run only writes the batch scripts)"
if [[ $mode == submit ]]; then
    node_cpus=""
    if ((have_slurm)); then
        node_cpus=$(sinfo -h -N ${partition:+-p "$partition"} -o %c 2>/dev/null | sort -n) ||
            ((dry_run)) || die "sinfo failed; is the Slurm controller reachable?"
        [[ -n $node_cpus ]] || ((dry_run)) || die "sinfo lists no nodes${partition:+ in partition '$partition'}"
    fi
    [[ -n $cpus ]] || cpus=$(head -n1 <<<"${node_cpus:-$(nproc)}")
    if [[ -n $node_cpus ]] && ((cpus > $(tail -n1 <<<"$node_cpus"))); then
        die "--cpus $cpus: the largest node has $(tail -n1 <<<"$node_cpus") CPUs"
    fi
fi

mkdir -p -- "$out/logs" # before sbatch: Slurm opens --output before the job starts
if [[ ! -x $out/vibroatlas ]]; then
    cp -p -- "$bin" "$out/vibroatlas.tmp" && mv -f -- "$out/vibroatlas.tmp" "$out/vibroatlas"
fi
name=${name:-$(basename -- "$out")}

# ---- the batch scripts (written once; --rerun and --merge-only reuse them) -------
# Values that may hold spaces (folders, the atlas words) are shell code in the
# body or sbatch arguments; #SBATCH lines hold plain words only.
if [[ $mode == submit && ! -f $out/run.txt ]]; then
    header() { # cpus per task
        echo "#!/bin/bash"
        echo "#SBATCH --nodes=1"
        echo "#SBATCH --ntasks=1"
        echo "#SBATCH --cpus-per-task=$1"
        [[ -z $partition ]] || echo "#SBATCH --partition=$partition"
        [[ -z $time_limit ]] || echo "#SBATCH --time=$time_limit"
        echo "# Written by scripts/slurm-atlas.sh: $run_line"
        echo "set -uo pipefail"
        echo "DIR=$(q "$out")"
        echo "SHARDS=$shards"
        echo "SLURM_ATLAS=\"$(q "$self") --out $(q "$out")\""
    }
    {
        header "$cpus"
        echo "cd $(q "$PWD") || exit 2 # where the run was submitted: relative paths resolve as they did there"
        echo "ATLAS=($(words "${atlas[@]}"))"
        cat <<'EOF'
k=${SLURM_ARRAY_TASK_ID:?not an array task: submit with sbatch --array=1-N}
((k >= 1 && k <= SHARDS)) || { echo "shard.sbatch: array task $k is not a shard 1..$SHARDS" >&2; exit 2; }
echo "shard $k/$SHARDS: job ${SLURM_JOB_ID:-?} on $(hostname), $(date -u +%FT%TZ)"
[[ ! -e $DIR/.part-$k-of-$SHARDS.h5.journal ]] || echo "shard $k/$SHARDS: its journal is there: vibroatlas resumes from it"
t0=$EPOCHREALTIME
"$DIR/vibroatlas" atlas "${ATLAS[@]}" --shard "$k/$SHARDS" --threads "${SLURM_CPUS_PER_TASK:-1}" --resume -o "$DIR/part-$k-of-$SHARDS.h5"
rc=$?
echo "shard $k/$SHARDS: vibroatlas exited $rc after $(awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.2f", b - a }') s"
((rc == 0)) || echo "shard $k/$SHARDS: rerun it with: $SLURM_ATLAS --rerun $k" >&2
exit $rc
EOF
    } >"$out/shard.sbatch"
    {
        header 1
        cat <<'EOF'
shopt -s nullglob
cd "$DIR" || exit 2
parts=(part-*-of-$SHARDS.h5)
((${#parts[@]})) || { echo "merge: no part-*-of-$SHARDS.h5 in $DIR" >&2; exit 2; }
"$DIR/vibroatlas" merge "${parts[@]}" "$@" -o atlas.h5 # "$@": --allow-missing or nothing
rc=$?
((rc == 0)) && echo "merge: wrote $DIR/atlas.h5" ||
    echo "merge: failed (exit $rc); compute missing shards with: $SLURM_ATLAS --rerun K[,K...]" >&2
exit $rc
EOF
    } >"$out/merge.sbatch"
    echo "$run_line" >"$out/run.txt"
fi

# ---- submission ------------------------------------------------------------------
submit() { # shard|merge, sbatch arguments...; prints the job id
    local what=$1 id
    shift
    if [[ $what == shard ]]; then
        set -- --job-name="$name" --output="$out/logs/shard-%A_%a.log" "$@"
    else
        set -- --job-name="$name-merge" --output="$out/logs/merge-%j.log" "$@"
    fi
    if ((dry_run)); then printf ' %q' sbatch --parsable "$@" >&2; echo >&2; echo "<$what-id>"; return; fi
    id=$(sbatch --parsable "$@" 2>&1) || die "sbatch $* failed: $id"
    echo "$(date -u +%FT%TZ) ${id%%;*}: sbatch $*" >>"$out/jobs.log"
    echo "${id%%;*}"
}
opts=() # the same for shards and merge
[[ -z $partition ]] || opts+=(--partition="$partition")
[[ -z $time_limit ]] || opts+=(--time="$time_limit")
array_id=""
((dry_run == 0)) || note "dry run: would run"
if [[ $mode == merge ]]; then
    extra=()
    ((allow_missing == 0)) || extra=(--allow-missing)
    merge_id=$(submit merge "${opts[@]}" "$out/merge.sbatch" "${extra[@]}")
    note "merge:  job $merge_id -> $out/atlas.h5"
else
    array=${rerun:-1-$shards}
    cpu_opt=()
    [[ -z $cpus ]] || cpu_opt=(--cpus-per-task="$cpus")
    array_id=$(submit shard --array="$array" "${opts[@]}" "${cpu_opt[@]}" "$out/shard.sbatch")
    merge_id=$(submit merge --dependency=afterok:"$array_id" --kill-on-invalid-dep=yes "${opts[@]}" "$out/merge.sbatch")
    note "shards: array job $array_id, tasks $array of $shards -> $out/part-K-of-$shards.h5"
    note "merge:  job $merge_id, when every task succeeded (cancelled if one fails) -> $out/atlas.h5"
fi
echo "jobs: array=${array_id:-none} merge=$merge_id"
if ((dry_run)); then note "dry run: nothing submitted; the batch scripts are in $out"; exit 0; fi
note "logs:   $out/logs/; rerun shards: $self --out $(q "$out") --rerun K[,K...]"
((wait)) || { note "watch:  squeue -j ${array_id:+$array_id,}$merge_id"; exit 0; }

# ---- --wait: until the jobs have left the queue, then the merge's end state ------
ids=${array_id:+$array_id,}$merge_id fails=0
while :; do
    if listed=$(squeue -h -j "$ids" 2>/dev/null); then
        [[ -n $listed ]] || break
        fails=0
    elif ((++fails >= 30)); then
        die "squeue -j $ids keeps failing; the jobs may still be queued or running"
    fi
    sleep 2
done
state=$(scontrol -o show job "$merge_id" 2>/dev/null | grep -o 'JobState=[A-Z_]* Reason=[^ ]*' | head -n1)
if [[ $state == JobState=COMPLETED* ]]; then note "done:   $out/atlas.h5"; exit 0; fi
note "FAILED: merge job $merge_id: ${state:-state unknown}"
[[ -z $array_id ]] || scontrol -o show job "$array_id" 2>/dev/null |
    sed -n 's/.*ArrayTaskId=\([0-9]*\) .*JobState=\([A-Z_]*\).*/  shard \1: \2/p' | grep -v COMPLETED
tail -n 3 "$out/logs/merge-$merge_id.log" 2>/dev/null | sed 's/^/  /'
exit 1

#!/usr/bin/env bash
# Submits one vibroatlas atlas to Slurm: a job array computing N shards, then a
# merge job that runs only when every shard succeeded. Run with --help.
set -euo pipefail

usage() {
    cat <<'EOF'
Usage:
  scripts/slurm-atlas.sh SCENE ATLAS-OPTIONS... --shards N [--out DIR] [--name NAME]
                         [--partition P] [--cpus C] [--time T] [--bin PATH] [--dry-run]
  scripts/slurm-atlas.sh --out DIR --rerun K[,K...]   [--partition P] [--cpus C] [--time T]
  scripts/slurm-atlas.sh --out DIR --merge-only [--allow-missing] [--partition P] [--time T]

Computes the atlas `vibroatlas atlas SCENE ATLAS-OPTIONS...` on a Slurm cluster as
a job array of N shards (whole lines each) and merges the parts into DIR/atlas.h5.

  SCENE ATLAS-OPTIONS  as for `vibroatlas atlas`, e.g. configs/multi-stop.toml
                       --x omega=0.1:3.05:296 --y delta=0.05:2:196 --sweep both.
                       --shard, --output/-o, --threads and --resume are set by
                       this script and refused here.
  --shards N           number of shards (array tasks); each writes DIR/part-K-of-N.h5
  --out DIR            run folder (default: $PWD/out/slurm-NAME, NAME defaulting to
                       SCENE-STEM-YYYYmmdd-HHMMSS); it must be on a file system the
                       compute nodes see. It receives a copy of the binary and the
                       scene, the generated batch scripts, the logs (DIR/logs/),
                       the parts, atlas.h5 and jobs.log (every submission).
  --name NAME          job name and default folder name
  --partition P        Slurm partition (default: the cluster's default partition)
  --cpus C             CPUs per shard = worker threads (default: the smallest CPU
                       count of the partition's nodes, from sinfo)
  --time T             time limit per job, as sbatch --time (default: the partition's)
  --bin PATH           vibroatlas binary (default: target/release/vibroatlas of this
                       checkout, or $VIBROATLAS_BIN); copied into DIR on first use
  --rerun K[,K...]     resubmit only these shards of the run in DIR, and a new merge
                       after them. A part that is already finished is kept (the task
                       is a no-op); an interrupted one continues from its journal.
  --merge-only         submit only the merge of the parts in DIR (no dependency)
  --allow-missing      with --merge-only: merge even with shards missing (their cells
                       stay "not computed")
  --dry-run            write the folder and batch scripts, print the sbatch commands,
                       submit nothing
  -h, --help           this text

Resubmitting the same SCENE and options with the same --out DIR submits every shard
again; finished parts are kept, so only the missing ones are computed.
With --rerun and --merge-only, SCENE and options may be left out (DIR/run.conf holds
them); if given, they must be those of the run.
EOF
}

prog=slurm-atlas
die() { echo "$prog: error: $*" >&2; exit 2; }
note() { echo "$prog: $*"; }

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
self="$repo/scripts/slurm-atlas.sh"

# Options of `vibroatlas atlas` that take a value (so that SCENE is found wherever it is).
atlas_value_opts=" --set --preset --accuracy --integrator --x --y --sweep --along --section-cap "

scene="" shards="" out="" name="" partition="" cpus="" time_limit="" rerun=""
merge_only=0 allow_missing=0 dry_run=0 bin="${VIBROATLAS_BIN:-}"
atlas_args=()

need() { [[ $# -ge 2 && -n $2 ]] || die "$1 needs a value (see --help)"; }
while (($#)); do
    a=$1
    case $a in
        -h | --help) usage; exit 0 ;;
        --shards | --out | --name | --partition | --cpus | --time | --rerun | --bin)
            need "$@"; v=$2; shift ;;&
        --shards=* | --out=* | --name=* | --partition=* | --cpus=* | --time=* | --rerun=* | --bin=*)
            v=${a#*=}; a=${a%%=*}; [[ -n $v ]] || die "$a needs a value" ;;&
        --shards | --shards=*) shards=$v ;;
        --out | --out=*) out=$v ;;
        --name | --name=*) name=$v ;;
        --partition | --partition=*) partition=$v ;;
        --cpus | --cpus=*) cpus=$v ;;
        --time | --time=*) time_limit=$v ;;
        --rerun | --rerun=*) rerun=$v ;;
        --bin | --bin=*) bin=$v ;;
        --merge-only) merge_only=1 ;;
        --allow-missing) allow_missing=1 ;;
        --dry-run) dry_run=1 ;;
        --shard | --shard=* | -o | --output | --output=* | --threads | --threads=* | --resume)
            die "${a%%=*} is set by this script, per shard; leave it out (see --help)" ;;
        --) shift; atlas_args+=("$@"); break ;;
        -*)
            atlas_args+=("$a")
            if [[ $atlas_value_opts == *" $a "* ]]; then
                [[ $# -ge 2 ]] || die "$a needs a value"
                atlas_args+=("$2"); shift
            fi ;;
        *)
            if [[ -z $scene ]]; then scene=$a; else die "unexpected argument '$a' (the scene is already '$scene')"; fi ;;
    esac
    shift
done

qwords() { (($#)) && printf '%q ' "$@"; return 0; } # shell-quoted words; nothing for none
is_count() { [[ $1 =~ ^[1-9][0-9]*$ ]]; }
[[ -z $shards ]] || is_count "$shards" || die "--shards must be a positive whole number, not '$shards'"
[[ -z $cpus ]] || is_count "$cpus" || die "--cpus must be a positive whole number, not '$cpus'"
((merge_only == 0 || ${#rerun} == 0)) || die "--rerun and --merge-only exclude each other"
((allow_missing == 0 || merge_only == 1)) || die "--allow-missing goes with --merge-only"
mode=submit
[[ -n $rerun ]] && mode=rerun
((merge_only)) && mode=merge

# ---- the run folder and its configuration -------------------------------------
if [[ -n $scene ]]; then
    [[ -f $scene && -r $scene ]] || die "scene '$scene' is not a readable file"
    scene=$(readlink -f -- "$scene")
fi

if [[ $mode == submit ]]; then
    [[ -n $scene ]] || die "no SCENE given (see --help)"
    [[ -n $shards ]] || die "--shards N is required"
    if [[ -z $out ]]; then
        stem=$(basename -- "$scene"); stem=${stem%.*}
        out="$PWD/out/slurm-${name:-$stem-$(date +%Y%m%d-%H%M%S)}"
    fi
else
    [[ -n $out ]] || die "--$( [[ $mode == rerun ]] && echo rerun || echo merge-only) needs --out DIR, the folder of the run"
    [[ -f $out/run.conf ]] || die "'$out' holds no run of this script (no run.conf)"
fi
out=$(readlink -m -- "$out")
[[ ! -e $out || -d $out ]] || die "'$out' exists and is not a folder"

# run.conf: what defines the run. Sourced back for --rerun and --merge-only.
RUN_SCENE="" RUN_ARGS=() RUN_SHARDS="" RUN_NAME="" RUN_PARTITION="" RUN_CPUS="" RUN_TIME="" RUN_BIN_SOURCE=""
if [[ -f $out/run.conf ]]; then
    # shellcheck source=/dev/null
    source "$out/run.conf"
    if [[ -n $scene ]]; then
        given=$(printf '%q ' "$scene" "${atlas_args[@]}")
        saved=$(printf '%q ' "$RUN_SCENE" "${RUN_ARGS[@]}")
        [[ $given == "$saved" ]] || die "'$out' holds another run:
    $saved
  not
    $given
  use another --out, or leave SCENE and its options out to reuse the saved ones"
    elif ((${#atlas_args[@]})); then
        die "atlas options given without SCENE; for --rerun/--merge-only leave both out"
    fi
    [[ -z $shards || $shards == "$RUN_SHARDS" ]] || die "'$out' is a run in $RUN_SHARDS shards, not $shards"
    scene=$RUN_SCENE atlas_args=("${RUN_ARGS[@]}") shards=$RUN_SHARDS
    name=${name:-$RUN_NAME}
    partition=${partition:-$RUN_PARTITION}
    time_limit=${time_limit:-$RUN_TIME}
    [[ $mode == merge ]] || cpus=${cpus:-$RUN_CPUS}
else
    if [[ -d $out && -n $(ls -A -- "$out") ]]; then
        die "'$out' exists and is not empty, but holds no run of this script; choose another --out"
    fi
fi
[[ -n $name ]] || { name=$(basename -- "$scene"); name=${name%.*}; }

# ---- which shards ---------------------------------------------------------------
array=""
if [[ $mode == submit ]]; then
    array="1-$shards"
elif [[ $mode == rerun ]]; then
    IFS=, read -r -a ks <<<"$rerun"
    ((${#ks[@]})) || die "--rerun needs shard numbers, e.g. --rerun 3 or --rerun 2,5"
    for k in "${ks[@]}"; do
        is_count "$k" && ((k <= shards)) || die "--rerun: '$k' is not a shard of this run (1..$shards)"
    done
    array=$(IFS=,; echo "${ks[*]}")
fi

# ---- CPUs per shard ------------------------------------------------------------
have_slurm=1
command -v sbatch >/dev/null 2>&1 && command -v sinfo >/dev/null 2>&1 || have_slurm=0
((have_slurm || dry_run)) || die "sbatch/sinfo not found: this script submits to Slurm (--dry-run only writes the scripts)"
if [[ $mode != merge ]]; then
    node_cpus=""
    if ((have_slurm)); then
        part=$partition
        if [[ -z $part ]]; then
            part=$(sinfo -h -o %P 2>/dev/null | sed -n 's/\*$//p' | head -n1) || true
        fi
        if ! node_cpus=$(sinfo -h -N ${part:+-p "$part"} -o %c 2>/dev/null | tr -dc '0-9\n' | sed '/^$/d' | sort -n); then
            ((dry_run)) || die "sinfo failed; is the Slurm controller reachable? (--dry-run only writes the scripts)"
            node_cpus=""
        fi
        [[ -n $node_cpus ]] || ((dry_run)) || die "sinfo lists no nodes${part:+ in partition '$part'}; check --partition"
    fi
    if [[ -z $cpus ]]; then
        if [[ -n $node_cpus ]]; then cpus=$(head -n1 <<<"$node_cpus"); else cpus=$(nproc); fi
    fi
    if [[ -n $node_cpus ]]; then
        max=$(tail -n1 <<<"$node_cpus")
        ((cpus <= max)) || die "--cpus $cpus: the largest node${part:+ in partition '$part'} has $max CPUs, so the shards would pend forever"
    fi
fi

# ---- check the binary, then create the run folder -------------------------------
run_bin="$out/vibroatlas"
if [[ ! -x $run_bin ]]; then
    bin=${bin:-$repo/target/release/vibroatlas}
    [[ -f $bin && -x $bin ]] || die "vibroatlas binary '$bin' not found or not executable (build it: cargo build --release, or pass --bin)"
    bin=$(readlink -f -- "$bin")
    "$bin" --version >/dev/null 2>&1 || die "'$bin' does not run on this machine"
fi
mkdir -p -- "$out" || die "cannot create '$out'"
[[ -w $out ]] || die "'$out' is not writable"

# The binary and the scene are copied into the run folder, so that every shard,
# rerun and merge of this run uses the same build and scene even if target/ is
# rebuilt or the scene edited meanwhile.
run_scene="$out/scene/$(basename -- "$scene")"
if [[ ! -x $run_bin ]]; then
    [[ ! -f $out/run.conf ]] ||
        note "warning: the run's copy of the binary is missing; copying $bin, which may be another build than the parts already computed"
    cp -p -- "$bin" "$run_bin.tmp" && mv -f -- "$run_bin.tmp" "$run_bin"
elif [[ -n $bin ]]; then
    note "note: using the run's own copy $run_bin, not --bin $bin"
    bin=""
fi
if [[ ! -f $run_scene ]]; then
    [[ -f $scene ]] || die "scene '$scene' of this run is gone and '$run_scene' is missing"
    mkdir -p -- "$out/scene"
    cp -p -- "$scene" "$run_scene"
fi
version=$("$run_bin" --version 2>/dev/null) || die "'$run_bin' does not run on this machine"

if [[ ! -f $out/run.conf ]]; then
    {
        echo "# vibroatlas run submitted by scripts/slurm-atlas.sh; do not edit"
        printf 'RUN_SCENE=%q\n' "$scene"
        printf 'RUN_ARGS=(%s)\n' "$(qwords "${atlas_args[@]}")"
        printf 'RUN_SHARDS=%q\n' "$shards"
        printf 'RUN_NAME=%q\n' "$name"
        printf 'RUN_PARTITION=%q\n' "$partition"
        printf 'RUN_CPUS=%q\n' "$cpus"
        printf 'RUN_TIME=%q\n' "$time_limit"
        printf 'RUN_BIN_SOURCE=%q\n' "${bin:-$run_bin}"
        printf 'RUN_VERSION=%q\n' "$version"
        printf 'RUN_CREATED=%q\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    } >"$out/run.conf"
fi

# ---- the batch scripts (kept in the run folder for the record) ------------------
mkdir -p -- "$out/logs" # before sbatch: Slurm opens --output before the script runs
sbatch_common() { # $1 = cpus
    echo "#SBATCH --nodes=1"
    echo "#SBATCH --ntasks=1"
    echo "#SBATCH --cpus-per-task=$1"
    echo "#SBATCH --chdir=$out"
    [[ -z $partition ]] || echo "#SBATCH --partition=$partition"
    [[ -z $time_limit ]] || echo "#SBATCH --time=$time_limit"
}
stamp=$(date -u +%Y-%m-%dT%H:%M:%SZ)

if [[ $mode != merge ]]; then
    cat >"$out/shard.sbatch" <<EOF
#!/bin/bash
# One shard of a vibroatlas atlas; generated by scripts/slurm-atlas.sh ($stamp).
# Array task ids are shard numbers, 1-based (0-based when the array contains 0).
#SBATCH --job-name=$name
#SBATCH --output=$out/logs/shard-%A_%a.log
$(sbatch_common "$cpus")
set -euo pipefail
SHARDS=$shards
RUN_DIR=$(printf %q "$out")
BIN=\$RUN_DIR/vibroatlas
SCENE=$(printf %q "$run_scene")
ARGS=($(qwords "${atlas_args[@]}"))
RERUN="$(printf %q "$self") --out $(printf %q "$out") --rerun"

id=\${SLURM_ARRAY_TASK_ID:-}
[[ -n \$id ]] || { echo "shard.sbatch: error: not a job-array task; submit it with sbatch --array=1-\$SHARDS" >&2; exit 2; }
if [[ \${SLURM_ARRAY_TASK_MIN:-1} == 0 ]]; then k=\$((id + 1)); else k=\$id; fi
if ((k < 1 || k > SHARDS)); then
    echo "shard.sbatch: error: array task \$id is shard \$k, outside 1..\$SHARDS" >&2
    exit 2
fi
threads=\${SLURM_CPUS_PER_TASK:-\$(nproc)}
part=part-\$k-of-\$SHARDS.h5
journal=.\$part.journal
cd "\$RUN_DIR"
echo "shard \$k/\$SHARDS: job \${SLURM_JOB_ID:-?} (array \${SLURM_ARRAY_JOB_ID:-?} task \$id) on \$(hostname), \$threads threads, \$("\$BIN" --version), \$(date -u +%FT%TZ)"

if [[ -e \$part ]]; then
    if [[ -f \$part ]] && info=\$("\$BIN" inspect "\$part" --json 2>&1) && [[ \$info =~ \"shard\"\ *:\ *\"\$k/\$SHARDS\" ]]; then
        echo "shard \$k/\$SHARDS: \$part is already finished; kept as it is (nothing to do)"
        exit 0
    fi
    echo "shard \$k/\$SHARDS: error: \$part exists but is not a finished shard \$k/\$SHARDS:" >&2
    echo "  \${info:-not a regular file}" | head -n 3 >&2
    echo "  move it away, then: \$RERUN \$k" >&2
    exit 2
fi
resume=()
if [[ -e \$journal ]]; then
    resume=(--resume)
    echo "shard \$k/\$SHARDS: \$journal found: resuming the interrupted run"
fi
set +e
"\$BIN" atlas "\$SCENE" "\${ARGS[@]}" --shard "\$k/\$SHARDS" --threads "\$threads" "\${resume[@]}" -o "\$part"
rc=\$?
set -e
if ((rc != 0)); then
    echo "shard \$k/\$SHARDS: FAILED (exit \$rc); rerun it with: \$RERUN \$k" >&2
    exit "\$rc"
fi
echo "shard \$k/\$SHARDS: wrote \$RUN_DIR/\$part, \$(date -u +%FT%TZ)"
EOF
fi

cat >"$out/merge.sbatch" <<EOF
#!/bin/bash
# Merge of the parts of a vibroatlas atlas; generated by scripts/slurm-atlas.sh ($stamp).
#SBATCH --job-name=$name-merge
#SBATCH --output=$out/logs/merge-%j.log
$(sbatch_common 1)
set -euo pipefail
SHARDS=$shards
RUN_DIR=$(printf %q "$out")
BIN=\$RUN_DIR/vibroatlas
SELF=$(printf %q "$self")
ALLOW_MISSING=$allow_missing
cd "\$RUN_DIR"
echo "merge: job \${SLURM_JOB_ID:-?} on \$(hostname), \$("\$BIN" --version), \$(date -u +%FT%TZ)"
parts=() missing=()
for ((k = 1; k <= SHARDS; k++)); do
    if [[ -f part-\$k-of-\$SHARDS.h5 ]]; then parts+=("part-\$k-of-\$SHARDS.h5"); else missing+=("\$k"); fi
done
if ((\${#missing[@]})); then
    list=\$(IFS=,; echo "\${missing[*]}")
    echo "merge: shards \$list of \$SHARDS have no part file; compute them with: \$SELF --out \$RUN_DIR --rerun \$list" >&2
fi
((\${#parts[@]})) || { echo "merge: error: no part file in \$RUN_DIR" >&2; exit 2; }
flags=()
((ALLOW_MISSING)) && flags+=(--allow-missing)
"\$BIN" merge "\${parts[@]}" "\${flags[@]}" -o atlas.h5
"\$BIN" inspect atlas.h5
echo "merge: wrote \$RUN_DIR/atlas.h5, \$(date -u +%FT%TZ)"
EOF
chmod +x "$out/merge.sbatch" "$out/shard.sbatch" 2>/dev/null || true

# ---- submission ----------------------------------------------------------------
submit() { # sbatch arguments...; prints the job id
    if ((dry_run)); then
        echo "  sbatch --parsable $*" >&2
        echo "$dry_id"
        return
    fi
    local reply
    reply=$(sbatch --parsable "$@" 2>&1) || die "sbatch $* failed: $reply"
    reply=${reply%%;*}
    [[ $reply =~ ^[0-9]+$ ]] || die "sbatch $* replied '$reply', not a job id"
    echo "$reply"
}
record() { ((dry_run)) || echo "$(date -u +%FT%TZ) $*" >>"$out/jobs.log"; }

array_id="" merge_id=""
((dry_run == 0)) || note "dry run: would submit"
if [[ $mode != merge ]]; then
    dry_id="<array-id>"
    array_id=$(submit --array="$array" "$out/shard.sbatch")
    record "array $array_id tasks=$array cpus=$cpus partition=${partition:-default} time=${time_limit:-default}: sbatch --parsable --array=$array $out/shard.sbatch"
    dry_id="<merge-id>"
    merge_id=$(submit --dependency=afterok:"$array_id" --kill-on-invalid-dep=yes "$out/merge.sbatch") || {
        echo "$prog: the shards are submitted (array job $array_id) but the merge is not; submit it later with:" >&2
        echo "  $self --out $out --merge-only" >&2
        exit 2
    }
    record "merge $merge_id after array $array_id: sbatch --parsable --dependency=afterok:$array_id --kill-on-invalid-dep=yes $out/merge.sbatch"
else
    dry_id="<merge-id>"
    merge_id=$(submit "$out/merge.sbatch")
    record "merge $merge_id (merge-only): sbatch --parsable $out/merge.sbatch"
fi

q() { printf '%q' "$1"; }
if ((dry_run)); then
    note "dry run: nothing submitted; the batch scripts are in $out (shard.sbatch, merge.sbatch)"
    exit 0
fi
note "run folder  $out"
note "binary      $run_bin ($version)"
if [[ -n $array_id ]]; then
    note "shards      array job $array_id, tasks $array of $shards, $cpus CPUs each -> part-K-of-$shards.h5 (logs/shard-${array_id}_K.log)"
    note "merge       job $merge_id, starts when every task succeeded, cancelled if one fails -> atlas.h5 (logs/merge-$merge_id.log)"
else
    note "merge       job $merge_id -> atlas.h5 (logs/merge-$merge_id.log)"
fi
echo "jobs: array=${array_id:-none} merge=$merge_id"
echo
echo "Watch:               squeue -j ${array_id:+$array_id,}$merge_id     (then: scontrol show job $merge_id; tail $(q "$out")/logs/*)"
echo "Rerun failed shards: $(q "$self") --out $(q "$out") --rerun K[,K...]"
echo "Merge again:         $(q "$self") --out $(q "$out") --merge-only"
echo "Result:              $(q "$out")/atlas.h5"

#!/usr/bin/env bash
# A Slurm job array computing one atlas in N shards, then merging them.
#   sbatch --array=1-8 scripts/slurm-atlas.sh            # eight shards
#   sbatch --dependency=afterok:<jobid> --wrap "target/release/vibroatlas merge out/part-*.h5 -o out/atlas.h5"
# Each shard computes whole lines (rows), so shards are independent; a shard that
# was killed is re-run with the same command plus --resume.
#SBATCH --job-name=vibroatlas
#SBATCH --cpus-per-task=8
#SBATCH --time=02:00:00
#SBATCH --output=out/slurm-%A_%a.log
set -euo pipefail
N=${SLURM_ARRAY_TASK_COUNT:-8}
K=${SLURM_ARRAY_TASK_ID:-1}
mkdir -p out
exec target/release/vibroatlas atlas configs/multi-stop.toml \
    --x omega=0.1:3.05:296 --y delta=0.05:2:196 --sweep both \
    --threads "${SLURM_CPUS_PER_TASK:-8}" --shard "$K/$N" --resume \
    -o "out/part-$K.h5"

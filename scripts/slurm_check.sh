#!/usr/bin/env bash
# The README's SLURM recipe run for real on the single-host cluster of
# scripts/local_slurm.sh (in a scratch folder, no system configuration touched): submits
# `suspflow generate GRID --shard I/3` as a job array of 3 tasks, waits for the array, merges
# the shards with `suspflow merge`, and checks with `cmp` that the merged dataset and
# ensemble table equal those of one single-process `generate` of the same grid byte for byte.
# Not part of the test suite (it installs packages and starts daemons); docs/slurm.md holds
# a run's output. Usage: scripts/slurm_check.sh [GRID] (default tests/grids/replicas.toml:
# 4 tiny runs, under a second each). SUSPFLOW names the binary (default target/release/suspflow).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
grid=${1:-tests/grids/replicas.toml}
suspflow=$(realpath "${SUSPFLOW:-target/release/suspflow}")
shards=3
[ -x "$suspflow" ] || { echo "no $suspflow: run cargo build --release first" >&2; exit 1; }

work=$(mktemp -d /tmp/suspflow-slurm.XXXXXX)
# The cluster is scripts/local_slurm.sh's (it installs slurm-wlm and munge when missing);
# only the daemons it started are ended, by the ids in their pid files.
trap 'scripts/local_slurm.sh stop "$work"' EXIT
scripts/local_slurm.sh start "$work"
# shellcheck source=/dev/null
source "$work/env"

echo "== the job array: $grid in $shards shards"
parts=$work/parts
mkdir -p "$parts"
cat >"$work/shards.sbatch" <<JOB
#!/bin/bash
#SBATCH --array=0-$((shards - 1)) --cpus-per-task=1 --time=00:05:00
#SBATCH --output=$work/shard.%a.log --chdir=$repo
nice -n 10 $suspflow generate $grid --out $parts/\$SLURM_ARRAY_TASK_ID/part.csv --shard \$SLURM_ARRAY_TASK_ID/$shards --threads 1
JOB
cat "$work/shards.sbatch"
started=$(date +%s)
sbatch --wait "$work/shards.sbatch"
echo "array finished in $(( $(date +%s) - started )) s"
for i in $(seq 0 $((shards - 1))); do
    echo "-- shard $i: $(grep -c . "$parts/$i/part.csv") lines in $parts/$i/part.csv"
    sed 's/^/   /' "$work/shard.$i.log"
done

echo "== merge, and the single-process generate of the same grid"
merged=$work/merged/all.csv
mkdir -p "$work/merged" "$work/single"
# One folder per shard: a glob such as part.*.csv would also take each shard's run table
# (part.N.scenes.csv), which merge refuses.
"$suspflow" merge "$parts"/*/part.csv --out "$merged"
nice -n 10 "$suspflow" generate "$grid" --out "$work/single/all.csv" --threads 1 >/dev/null
ls -l "$work/merged" "$work/single"
status=0
for f in all.csv all.ensemble.csv; do
    if [ -e "$work/single/$f" ] || [ -e "$work/merged/$f" ]; then
        if cmp "$work/merged/$f" "$work/single/$f"; then
            echo "identical: $f ($(wc -l <"$work/merged/$f") lines, $(wc -c <"$work/merged/$f") bytes)"
        else
            status=1
        fi
    fi
done
[ $status = 0 ] && echo "PASS: the merged shards equal the single-process generate byte for byte" \
    || echo "FAIL: the merged shards differ from the single-process generate"
exit $status

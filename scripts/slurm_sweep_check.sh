#!/usr/bin/env bash
# A sweep that survives a cluster, tried for real (docs/slurm.md): on a single-host SLURM
# (scripts/local_slurm.sh), every run of GRID (default tests/grids/sweep.toml: 100 runs) is
# one task of a job array with a throttle, a one-minute time limit whose SIGTERM comes
# before the kill (--signal), and a requeue of a task that stopped with its checkpoint
# (`suspflow` exits 75); a merge job waits for the array (--dependency=afterany). Mid-way
# a running task is cancelled and the node is set DOWN under the running ones, then back; the merge job finds
# the array incomplete, the missing tasks are resubmitted with a new merge job, and the
# merged table is compared with `cmp` against one single-process `generate` of the grid.
# Counts: runs in the merged table (none lost), and runs finished more than once (none),
# from the tasks' logs. Not part of the test suite (it installs packages, starts daemons).
# Usage: scripts/slurm_sweep_check.sh [GRID]; SUSPFLOW names the binary.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
grid=$(realpath "${1:-tests/grids/sweep.toml}")
suspflow=$(realpath "${SUSPFLOW:-target/release/suspflow}")
[ -x "$suspflow" ] || { echo "no $suspflow: run cargo build --release first" >&2; exit 1; }
work=$(mktemp -d /tmp/suspflow-sweep.XXXXXX)
trap 'scripts/local_slurm.sh stop "$work/cluster"' EXIT
scripts/local_slurm.sh start "$work/cluster"
# shellcheck disable=SC1091
source "$work/cluster/env"
runs=$("$suspflow" generate "$grid" --out "$work/check.csv" --check | tail -1 | cut -d' ' -f1)
echo "== $grid: $runs runs, one array task each ($suspflow --version: $("$suspflow" --version))"
parts=$work/parts
mkdir -p "$work/logs" "$parts" "$work/merged"

cat >"$work/run.sbatch" <<JOB
#!/bin/bash
#SBATCH --job-name=sweep --cpus-per-task=1 --time=1 --signal=B:TERM@30 --requeue
#SBATCH --open-mode=append --output=$work/logs/task.%a.log --chdir=$repo
# One run of the grid per task. SIGTERM (the time limit's signal, or scancel) is passed to
# suspflow, which saves its checkpoint and exits 75 (interrupted); the task then requeues
# itself, and its next start resumes the run.
echo "task \$SLURM_ARRAY_TASK_ID (job \$SLURM_JOB_ID, restart \${SLURM_RESTART_COUNT:-0}) on \$(hostname)"
$suspflow generate $grid --out $parts/\$SLURM_ARRAY_TASK_ID/part.csv --shard \$SLURM_ARRAY_TASK_ID/$runs --threads 1 &
pid=\$!
trap 'kill -TERM \$pid' TERM
while true; do
    wait \$pid
    status=\$?
    kill -0 \$pid 2>/dev/null || break
done
echo "task \$SLURM_ARRAY_TASK_ID: suspflow exited with status \$status"
if [ \$status -eq 75 ]; then
    scontrol requeue \${SLURM_ARRAY_JOB_ID}_\${SLURM_ARRAY_TASK_ID}
fi
exit \$status
JOB

cat >"$work/merge.sbatch" <<JOB
#!/bin/bash
#SBATCH --job-name=merge --open-mode=append --output=$work/logs/merge.log --chdir=$repo
# Merges the parts once every task's run is done; otherwise names the missing tasks and
# exits 3 (runs not done), writing nothing.
missing=()
for i in \$(seq 0 $((runs - 1))); do
    grep -q '^[^,]*,done,' $parts/\$i/part.scenes.csv 2>/dev/null || missing+=(\$i)
done
if [ \${#missing[@]} -gt 0 ]; then
    echo "merge: \${#missing[@]} task(s) not done: \$(IFS=,; echo "\${missing[*]}")"
    exit 3
fi
$suspflow merge $parts/*/part.csv --out $work/merged/all.csv --force
JOB
echo "-- run.sbatch"; sed 's/^/   /' "$work/run.sbatch"
echo "-- merge.sbatch"; sed 's/^/   /' "$work/merge.sbatch"

wait_for() { # job id: waits until it has left the queue
    while squeue -h -j "$1" 2>/dev/null | grep -q .; do sleep 2; done
}
done_tasks() {
    grep -l "suspflow exited with status 0" "$work"/logs/task.*.log 2>/dev/null | wc -l
}

started=$(date +%s)
array=$(sbatch --parsable --array=0-$((runs - 1))%4 "$work/run.sbatch")
merge=$(sbatch --parsable --dependency=afterany:"$array" "$work/merge.sbatch")
echo "== submitted array $array (throttle 4) and merge job $merge (afterany:$array)"
running() { # task: whether it is running
    squeue -h -j "${array}_$1" -t RUNNING -o %i 2>/dev/null | grep -q .
}
# The long runs are the last tasks: cancel one of them mid-run (its checkpoint is a second
# old at most), then fail the node under whatever runs next.
until running $((runs - 4)); do sleep 1; done
sleep 10
echo "== $(done_tasks) tasks done at $(( $(date +%s) - started )) s; killed: scancel --signal=KILL --full ${array}_$((runs - 4)) (running)"
# SIGKILL, not a signal it could answer: the task loses what it did since its last
# checkpoint, is not requeued, and has to be resubmitted.
scancel --signal=KILL --full "${array}_$((runs - 4))"
until squeue -h -j "$array" -t RUNNING -o %i | grep -q .; do sleep 1; done
sleep 5
echo "== the node fails at $(( $(date +%s) - started )) s: scontrol update NodeName=localhost State=DOWN; running then:"
squeue -j "$array" -t RUNNING -o "%.12i %.8T %.10M" | sed 's/^/   /'
scontrol update NodeName=localhost State=DOWN Reason="failing on purpose"
sleep 5
sinfo | sed 's/^/   /'
squeue -j "$array" -o "%.14i %.9T %.20r" | head -8 | sed 's/^/   /'
# ReturnToService=2 may already have taken it back.
scontrol update NodeName=localhost State=RESUME 2>/dev/null || true
echo "== node back at $(( $(date +%s) - started )) s"
wait_for "$merge"
echo "== merge job $merge ended at $(( $(date +%s) - started )) s:"
sed 's/^/   /' "$work/logs/merge.log"
missing=$(sed -n 's/^merge: .* not done: //p' "$work/logs/merge.log" | tail -1)
if [ -n "$missing" ]; then
    again=$(sbatch --parsable --array="$missing" "$work/run.sbatch")
    merge=$(sbatch --parsable --dependency=afterany:"$again" "$work/merge.sbatch")
    echo "== resubmitted tasks $missing as array $again, merge job $merge (afterany:$again)"
    wait_for "$merge"
    echo "== merge job $merge ended at $(( $(date +%s) - started )) s:"
    tail -n +2 "$work/logs/merge.log" | sed 's/^/   /'
fi

echo "== what the tasks' logs say"
logs=("$work"/logs/task.*.log)
echo "task starts: $(grep -h -c '^task [0-9]* (job' "${logs[@]}" | paste -sd+ | bc), of which restarts: $(grep -h '^task [0-9]* (job' "${logs[@]}" | grep -vc 'restart 0)')"
echo "exit statuses: $(grep -h 'suspflow exited with status' "${logs[@]}" | awk '{print $NF}' | sort | uniq -c | awk '{printf "%s x %s, ", $1, $2}')"
echo "runs started afresh: $(grep -h ' start: ' "${logs[@]}" | wc -l), resumed from a checkpoint: $(grep -h ' start (resuming): ' "${logs[@]}" | wc -l), interrupted: $(grep -h ' interrupted at step ' "${logs[@]}" | wc -l)"
finished=$(grep -h ' done in ' "${logs[@]}" | awk '{print $1}' | sort)
twice=$(echo "$finished" | uniq -d | wc -l)
echo "runs finished: $(echo "$finished" | grep -c .), distinct: $(echo "$finished" | uniq | grep -c .), finished more than once: $twice"

echo "== the single-process generate of the same grid"
mkdir -p "$work/single"
nice -n 10 "$suspflow" generate "$grid" --out "$work/single/all.csv" --threads 1 >/dev/null 2>&1
status=0
in_table=$(cut -d, -f1,5 "$work/merged/all.csv" | tail -n +2 | sort -u | wc -l)
echo "runs in the merged table: $in_table of $runs; lost: $((runs - in_table))"
[ "$in_table" = "$runs" ] && [ "$twice" = 0 ] || status=1
for f in all.csv all.ensemble.csv; do
    if cmp "$work/merged/$f" "$work/single/$f"; then
        echo "identical: $f ($(wc -l <"$work/merged/$f") lines, $(wc -c <"$work/merged/$f") bytes)"
    else
        status=1
    fi
done
echo "total $(( $(date +%s) - started )) s"
[ $status = 0 ] && echo "PASS: no run lost, none finished twice, the merged table equals the single-process generate byte for byte" \
    || echo "FAIL"
exit $status

#!/usr/bin/env bash
# An experiment driver's grid on a SLURM cluster: a job array of N shards (`--shard I/N`, one per array task),
# then a merge job that runs after all of them succeeded (`--merge-shards N`) and writes the Markdown reports.
#   scripts/slurm_shards.sh N DRIVER [DRIVER ARGS...]     e.g. scripts/slurm_shards.sh 8 table_2_1 --full
# DRIVER is table_2_1 or solvers (build/exp_DRIVER); the same ARGS go to every shard and to the merge, so they
# describe one grid. Run it from the repository root on a filesystem the nodes share: the shards write
# RESULTS/shards/I-of-N/ (RESULTS: --results; table_2_1's default results/, solvers requires it), the merge RESULTS/. SBATCH_* variables and
# SLURM_SHARD_OPTS (extra sbatch options, e.g. "--partition=long --time=4:00:00") adjust the jobs; each task asks
# for one node's worth of memory by default, since a cell's budget is half the RAM it finds.
set -euo pipefail
(($# >= 2)) || { echo "usage: scripts/slurm_shards.sh N DRIVER [DRIVER ARGS...]" >&2; exit 1; }
n=$1 driver=$2
shift 2
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "slurm_shards.sh: N must be a positive whole number, not '$n'" >&2; exit 1; }
case $driver in table_2_1 | solvers) ;; *) echo "slurm_shards.sh: DRIVER is table_2_1 or solvers" >&2; exit 1 ;; esac
exe=build/exp_$driver
[ -x "$exe" ] || { echo "slurm_shards.sh: $exe not built (cmake --build build --target exp_$driver)" >&2; exit 1; }
"$exe" "$@" --shard "1/$n" --dry-run >/dev/null  # the options are checked here, not in n queued jobs
results=""
for ((i = 1; i <= $#; ++i)); do [ "${!i}" = --results ] && { j=$((i + 1)); results=${!j}; }; done
# exp_solvers refuses to run without --results (a dry run does not need it): refused here, not in every job.
[ -n "$results" ] || [ "$driver" != solvers ] ||
  { echo "slurm_shards.sh: solvers needs --results DIR (where the shards and the merged CSVs go)" >&2; exit 1; }
results=${results:-results}

args=$(printf ' %q' "$@")
read -r -a extra <<<"${SLURM_SHARD_OPTS:-}"
jid=$(sbatch --parsable --job-name="db-$driver" --array="1-$n" --nodes=1 --exclusive "${extra[@]}" \
  --wrap="$exe$args --shard \$SLURM_ARRAY_TASK_ID/$n")
sbatch --parsable --job-name="db-$driver-merge" --dependency="afterok:$jid" "${extra[@]}" \
  --wrap="$exe$args --merge-shards $n && PYTHONPATH=python /usr/bin/python3 -m dbtools.report --only $driver --results $(printf %q "$results")"
echo "submitted shards $jid (1-$n) and their merge" >&2

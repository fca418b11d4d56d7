#!/bin/bash
# One line of a sweep's jobs.txt per SLURM array task (docs/EXPERIMENTS.md, "Cluster"):
#   sbatch --array=1-$(wc -l < OUT/jobs.txt)%32 tools/experiments/slurm-array.sh OUT/jobs.txt
#SBATCH --job-name=budget-slam
#SBATCH --cpus-per-task=4
#SBATCH --time=01:00:00
#SBATCH --signal=INT@60
#SBATCH --output=slurm-%A_%a.out
set -u
line=$(sed -n "${SLURM_ARRAY_TASK_ID}p" "$1")
[ -n "$line" ] || { echo "no line ${SLURM_ARRAY_TASK_ID} in $1" >&2; exit 2; }
srun bash -c "$line"

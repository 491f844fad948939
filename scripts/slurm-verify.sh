#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# plancheck verify (or sweep) as a Slurm job array of N shards, then one
# dependent merge job (contract: shared/spec/plan-and-report-format.md,
# "Beyond one machine"). Run from the folder the paths are relative to
# (merge reads the scene and plans again, as the shards named them):
#
#   scripts/slurm-verify.sh N OUT plancheck verify SCENE.json PLAN.csv... [options]
#
# Each array task i writes OUT/part-i/part-i-of-N.plancheck; the merge job
# writes OUT/merged (report.json, the CSVs, ... as one run would) and exits
# 0 all safe, 1 a violation, 2 a bad or missing shard. A failed or
# cancelled task can be run again alone with --resume (sbatch --array=i).
# Extra sbatch options: SBATCH_ARGS="--partition=... --time=..." in the
# environment.
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 N OUT plancheck verify|sweep SCENE ... (plancheck's own arguments, no --out/--shard)" >&2
  exit 2
fi
n=$1 out=$2
shift 2
exe=$1
shift
mkdir -p "$out"
quoted=$(printf ' %q' "$@")
array=$(sbatch --parsable ${SBATCH_ARGS:-} --array=0-$((n - 1)) --job-name=plancheck-shard \
  --output="$out/shard-%a.log" --wrap="$(printf %q "$exe")$quoted --quiet --resume \
  --shard \$SLURM_ARRAY_TASK_ID/\$SLURM_ARRAY_TASK_COUNT --out $(printf %q "$out")/part-\$SLURM_ARRAY_TASK_ID")
parts=$(for ((i = 0; i < n; i++)); do printf ' %q' "$out/part-$i"; done)
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency=afterok:"$array" --job-name=plancheck-merge \
  --output="$out/merge.log" --wrap="$(printf %q "$exe") merge$parts --out $(printf %q "$out")/merged")
echo "shards: job $array (array 0-$((n - 1))), merge: job $merge -> $out/merged"

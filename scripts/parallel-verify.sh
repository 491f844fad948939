#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# plancheck verify (or sweep) as N shards on one machine or over ssh with
# GNU parallel, then merge (docs/scale-out.md):
#
#   scripts/parallel-verify.sh N OUT plancheck verify SCENE.json PLAN.csv... [options]
#
# The one-liner it runs, for N = 4:
#   parallel plancheck verify SCENE PLANS --quiet --shard {}/4 --out OUT/part-{} ::: 0 1 2 3 &&
#     plancheck merge OUT/part-{0,1,2,3} --out OUT/merged
# Without GNU parallel (PLANCHECK_NO_PARALLEL=1, or parallel not found) the
# shards run as background jobs of this shell: the same files.
set -uo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 N OUT plancheck verify|sweep SCENE ... (plancheck's own arguments, no --out/--shard)" >&2
  exit 2
fi
n=$1 out=$2
shift 2
exe=$1
shift
mkdir -p "$out"
if [ -z "${PLANCHECK_NO_PARALLEL:-}" ] && command -v parallel > /dev/null; then
  parallel --halt now,fail=1 "$exe" "$@" --quiet --shard "{}/$n" --out "$out/part-{}" ::: $(seq 0 $((n - 1))) || exit 2
else
  pids=()
  for ((i = 0; i < n; i++)); do
    "$exe" "$@" --quiet --shard "$i/$n" --out "$out/part-$i" & pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid" || exit 2; done
fi
parts=()
for ((i = 0; i < n; i++)); do parts+=("$out/part-$i"); done
exec "$exe" merge "${parts[@]}" --out "$out/merged"

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# sweep beyond one process (src/cli/distribute.h), end to end on the
# generated dataset: shards (2 and 3) + merge of a certified sweep (with
# --html), of an --exact-distance --csv sweep and of a certified sweep of
# the scene without terrain; --resume after a kill; merge refusing a shard
# of another grid; and (when given an mpirun) mpirun -np 3. Each compared
# with a single run by compare_runs.py (files, bytes, JSON but for timing
# fields) and the single run's stdout (but for the timing line).
# Usage: sweep_distribute_test.sh PLANCHECK DATASET SCRATCH [MPIRUN]
set -u
exe=$1 data=$2 work=$3 mpirun=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
compare="python3 $here/compare_runs.py"
failures=0
bad() { echo "FAIL: $*"; failures=$((failures + 1)); }
rm -rf "$work" && mkdir -p "$work"
scene=$data/scene.json
python3 "$here/compare_runs.py" --no-terrain "$scene" "$work/no-terrain.json"
# 4 certified blocks of unequal sizes (16 values an axis a block).
grid="J1=-180:180:20,J2=-20:130:10,J3=-160:0:40,J4=-80:140:10"
# One 2^16-row item with --csv (each configuration checked on its own costs ~0.4 ms).
small="J1=-40:40:20,J2=-20:130:30,J3=-160:0:40,J4=-80:140:40"

# run NAME ARGS...: sweep into $work/NAME, stdout (timing line cut) in NAME.out, status in NAME.rc.
run() {
  local name=$1; shift
  "$exe" sweep "$@" --out "$work/$name" --quiet > "$work/$name.stdout" 2> "$work/$name.err"
  echo $? > "$work/$name.rc"
  grep -v ' configurations, .* s (load' "$work/$name.stdout" > "$work/$name.out"
}
merge() {
  local name=$1; shift
  "$exe" merge "$@" --out "$work/$name" --quiet > "$work/$name.stdout" 2> "$work/$name.err"
  echo $? > "$work/$name.rc"
  grep -v ' configurations, .* s (load' "$work/$name.stdout" > "$work/$name.out"
}
# same A B: B's folder, stdout and status are A's.
same() {
  $compare "$work/$1" "$work/$2" || bad "$2 differs from $1"
  cmp -s "$work/$1.out" "$work/$2.out" || bad "$2's stdout differs from $1's"
  cmp -s "$work/$1.rc" "$work/$2.rc" || bad "$2's status $(cat "$work/$2.rc") is not $1's $(cat "$work/$1.rc")"
}

# 1. Shards + merge = one run (3 shards, and 2 for the certified one).
for variant in "cert:$scene --grid $grid --html" "each:$scene --grid $small --exact-distance --csv" \
               "flat:$work/no-terrain.json --grid $grid"; do
  name=${variant%%:*}; read -r -a args <<< "${variant#*:}"
  run "$name-single" "${args[@]}" --threads 2
  [ "$(cat "$work/$name-single.rc")" = 0 ] || bad "$name single run: status $(cat "$work/$name-single.rc"): $(cat "$work/$name-single.err")"
  for n in 3 2; do
    [ $n = 2 ] && [ "$name" != cert ] && continue
    for ((i = 0; i < n; i++)); do run "$name-$n-part$i" "${args[@]}" --threads 1 --shard "$i/$n" & done
    wait
    dirs=()
    for ((i = n - 1; i >= 0; i--)); do
      [ "$(cat "$work/$name-$n-part$i.rc")" = 0 ] || bad "$name shard $i/$n: status $(cat "$work/$name-$n-part$i.rc"): $(cat "$work/$name-$n-part$i.err")"
      [ "$(ls -A "$work/$name-$n-part$i")" = "part-$i-of-$n.plancheck" ] || bad "$name shard $i/$n wrote $(ls -A "$work/$name-$n-part$i")"
      dirs+=("$work/$name-$n-part$i")
    done
    merge "$name-$n-merged" "${dirs[@]}"
    same "$name-single" "$name-$n-merged"
  done
done
[ -s "$work/each-single/sweep.csv" ] || bad "the --csv run wrote no sweep.csv"
[ -s "$work/cert-single/sweep.html" ] || bad "the --html run wrote no sweep.html"

# 2. An interrupted run (the test hook ends it as a kill would, after one
#    item) leaves its journal; --resume redoes only the rest: same files, no journal.
PLANCHECK_TEST_STOP_AFTER=1 "$exe" sweep "$scene" --grid "$grid" --html --out "$work/resumed" --quiet > /dev/null 2>&1
rc=$?
[ $rc = 75 ] || bad "the interrupted run's status is $rc, not 75"
[ -s "$work/resumed/.plancheck-journal" ] || bad "the interrupted run left no journal"
"$exe" sweep "$scene" --grid "$grid" --html --resume --out "$work/resumed" > "$work/resumed.stdout" 2> "$work/resumed.err"
echo $? > "$work/resumed.rc"
grep -v ' configurations, .* s (load' "$work/resumed.stdout" > "$work/resumed.out"
grep -q 'resume: [1-9][0-9]* of [0-9]* items done' "$work/resumed.err" || bad "--resume did not reuse the journal: $(cat "$work/resumed.err")"
same cert-single resumed
PLANCHECK_TEST_STOP_AFTER=1 "$exe" sweep "$scene" --grid "$small" --exact-distance --csv --out "$work/resumed-each" --quiet > /dev/null 2>&1
[ -s "$work/resumed-each/.plancheck-journal" ] || bad "the interrupted --csv run left no journal"
run resumed-each "$scene" --grid "$small" --exact-distance --csv --resume
same each-single resumed-each

# 3. merge refuses a shard of another grid, and a resumed run of another grid.
run other-part1 "$scene" --grid "$small" --shard 1/3
out=$("$exe" merge "$work/cert-3-part0" "$work/other-part1" "$work/cert-3-part2" --out "$work/refused" --quiet 2>&1)
rc=$?
[ $rc = 2 ] && grep -q 'not of the same run' <<< "$out" || bad "merge of another grid's shard: status $rc: $out"
[ ! -e "$work/refused/sweep.json" ] || bad "the refused merge left a sweep.json"
PLANCHECK_TEST_STOP_AFTER=1 "$exe" sweep "$scene" --grid "$grid" --out "$work/other" --quiet > /dev/null 2>&1
"$exe" sweep "$scene" --grid "$small" --out "$work/other" --resume --quiet > /dev/null 2> "$work/other.err"
rc=$?
[ $rc = 2 ] && grep -q 'another run' "$work/other.err" || bad "resume of another grid: status $rc: $(cat "$work/other.err")"

# 4. mpirun -np 3 (one thread a rank): the single run's files and stdout.
if [ -n "$mpirun" ]; then
  "$mpirun" --oversubscribe --allow-run-as-root -np 3 "$exe" sweep "$scene" --grid "$grid" --html \
    --threads 1 --out "$work/mpi" --quiet > "$work/mpi.stdout" 2> "$work/mpi.err"
  echo $? > "$work/mpi.rc"
  grep -v ' configurations, .* s (load' "$work/mpi.stdout" > "$work/mpi.out"
  same cert-single mpi
  python3 -c "import json,sys; r=json.load(open(sys.argv[1])); assert r['ranks']==3 and r['seconds']['chunks'], r" \
    "$work/mpi/sweep.json" || bad "the MPI sweep.json has no ranks or chunk times"
fi

[ $failures -eq 0 ] && echo "sweep_distribute: all passed" && rm -rf "$work"
exit $((failures > 0))

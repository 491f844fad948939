#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# verify beyond one process (src/cli/distribute.h), end to end on the
# generated dataset: shards + merge, --resume after a kill, merge's
# refusals, and (when given an mpirun) mpirun -np 3; each compared with a
# single run by compare_runs.py (files, bytes, JSON but for timing fields),
# with the single run's stdout (but for the timing line) and exit status.
# Usage: verify_distribute_test.sh PLANCHECK DATASET SCRATCH [MPIRUN]
set -u
exe=$1 data=$2 work=$3 mpirun=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
compare="python3 $here/compare_runs.py"
failures=0
bad() { echo "FAIL: $*"; failures=$((failures + 1)); }
rm -rf "$work" && mkdir -p "$work"
# Three plans: a safe one, a collision, a clearance violation (terrain, scoop, probes).
plans=("$data/plans/plan06.csv" "$data/plans/plan04.csv" "$data/plans/plan07.csv")
scene=$data/scene.json
python3 "$here/compare_runs.py" --no-terrain "$scene" "$work/no-terrain.json"

# run NAME ARGS...: verify into $work/NAME, stdout (timing line cut) in NAME.out, status in NAME.rc.
run() {
  local name=$1; shift
  "$exe" verify "$@" --out "$work/$name" --quiet > "$work/$name.stdout" 2> "$work/$name.err"
  echo $? > "$work/$name.rc"
  grep -v ' plans, .* states, .* s (load' "$work/$name.stdout" > "$work/$name.out"
}
# same A B: B's folder, stdout and status are A's.
same() {
  $compare "$work/$1" "$work/$2" || bad "$2 differs from $1"
  cmp -s "$work/$1.out" "$work/$2.out" || bad "$2's stdout differs from $1's"
  cmp -s "$work/$1.rc" "$work/$2.rc" || bad "$2's status $(cat "$work/$2.rc") is not $1's $(cat "$work/$1.rc")"
}
merge() {
  local name=$1; shift
  "$exe" merge "$@" --out "$work/$name" --quiet > "$work/$name.stdout" 2> "$work/$name.err"
  echo $? > "$work/$name.rc"
  grep -v ' plans, .* states, .* s (load' "$work/$name.stdout" > "$work/$name.out"
}
# refused NAME WORD DIR...: merge exits 2 with one message containing WORD.
refused() {
  local name=$1 word=$2; shift 2
  "$exe" merge "$@" --out "$work/$name" --quiet > /dev/null 2> "$work/$name.err"
  local rc=$?
  [ $rc -eq 2 ] || bad "merge $name: status $rc, not 2"
  [ "$(wc -l < "$work/$name.err")" -eq 1 ] || bad "merge $name: not one line: $(cat "$work/$name.err")"
  grep -q -- "$word" "$work/$name.err" || bad "merge $name: '$word' not in: $(cat "$work/$name.err")"
  [ ! -e "$work/$name/report.json" ] || bad "merge $name left a report.json"
}

# 1. Shards + merge = one run: terrain and digging with --continuous --html;
#    no terrain; --dig-carry (one item: shard 0 does all, the others none).
for variant in "cont:$scene --continuous --html" "flat:$work/no-terrain.json --continuous" "carry:$scene --dig-carry"; do
  name=${variant%%:*}; read -r -a args <<< "${variant#*:}"
  run "$name-single" "${args[@]}" "${plans[@]}"
  for i in 0 1 2; do run "$name-part$i" "${args[@]}" "${plans[@]}" --shard "$i/3" & done
  wait
  for i in 0 1 2; do
    [ "$(cat "$work/$name-part$i.rc")" = 0 ] || bad "$name shard $i: status $(cat "$work/$name-part$i.rc"): $(cat "$work/$name-part$i.err")"
    [ "$(ls -A "$work/$name-part$i")" = "part-$i-of-3.plancheck" ] || bad "$name shard $i wrote $(ls -A "$work/$name-part$i")"
  done
  merge "$name-merged" "$work/$name-part2" "$work/$name-part0" "$work/$name-part1"
  same "$name-single" "$name-merged"
done
grep -q 'between states' "$work/cont-single.out" || bad "the --continuous run shows no violation between states"
[ "$(cat "$work/cont-single.rc")" = 1 ] || bad "the single run's status is not 1"

# Shards sharing one folder merge the same.
for i in 0 1; do run shared "$scene" "${plans[@]}" --shard "$i/2"; done
run plain-single "$scene" "${plans[@]}"
merge shared-merged "$work/shared"
same plain-single shared-merged

# 2. An interrupted run (the test hook ends it as a kill would, after one
#    plan) leaves its journal; --resume redoes only the rest: same files, no journal.
PLANCHECK_TEST_STOP_AFTER=1 "$exe" verify "$scene" "${plans[@]}" --continuous --html --out "$work/resumed" --quiet > /dev/null 2>&1
rc=$?
[ $rc = 75 ] || bad "the interrupted run's status is $rc, not 75"
[ -s "$work/resumed/.plancheck-journal" ] || bad "the interrupted run left no journal"
"$exe" verify "$scene" --continuous --html "${plans[@]}" --resume --out "$work/resumed" > "$work/resumed.stdout" 2> "$work/resumed.err"
echo $? > "$work/resumed.rc"
grep -v ' plans, .* states, .* s (load' "$work/resumed.stdout" > "$work/resumed.out"
grep -q 'resume: 1 of 3 items done' "$work/resumed.err" || bad "--resume did not reuse the journal: $(cat "$work/resumed.err")"
same cont-single resumed
# A resumed run of other options is refused.
PLANCHECK_TEST_STOP_AFTER=1 "$exe" verify "$scene" "${plans[@]}" --out "$work/other" --quiet > /dev/null 2>&1
"$exe" verify "$scene" "${plans[@]}" --continuous --out "$work/other" --resume --quiet > /dev/null 2> "$work/other.err"
rc=$?
[ $rc = 2 ] && grep -q 'another run' "$work/other.err" || bad "resume of another run: status $rc: $(cat "$work/other.err")"

# A killed shard: merge refuses it; --resume completes it; then the merge is the run's.
PLANCHECK_TEST_STOP_AFTER=1 "$exe" verify "$scene" --continuous --html "${plans[@]}" --shard 0/3 --out "$work/killed" --quiet > /dev/null 2>&1
refused cut-short "cut short" "$work/killed" "$work/cont-part1" "$work/cont-part2"
run killed "$scene" --continuous --html "${plans[@]}" --shard 0/3 --resume
merge killed-merged "$work/killed" "$work/cont-part1" "$work/cont-part2"
same cont-single killed-merged

# 3. merge refuses what is not all the shards of one run.
refused missing "shard 1 of 3 missing" "$work/cont-part0" "$work/cont-part2"
mkdir -p "$work/again" && cp "$work/cont-part0/part-0-of-3.plancheck" "$work/again/"
refused repeated "given twice" "$work/cont-part0" "$work/again" "$work/cont-part1" "$work/cont-part2"
refused other-options "not of the same run" "$work/cont-part0" "$work/carry-part1" "$work/cont-part2"
refused other-scene "not of the same run" "$work/cont-part0" "$work/flat-part1" "$work/cont-part2"
mkdir -p "$work/truncated" && head -c -9 "$work/cont-part1/part-1-of-3.plancheck" > "$work/truncated/part-1-of-3.plancheck"
refused truncated "cut short" "$work/cont-part0" "$work/truncated" "$work/cont-part2"
mkdir -p "$work/flipped" && cp "$work/cont-part1/part-1-of-3.plancheck" "$work/flipped/"
size=$(stat -c %s "$work/flipped/part-1-of-3.plancheck")
printf 'X' | dd of="$work/flipped/part-1-of-3.plancheck" bs=1 seek=$((size / 2)) conv=notrunc status=none
refused corrupt "corrupt" "$work/cont-part0" "$work/flipped" "$work/cont-part2"
# Bad --shard values are input errors naming the flag.
for v in 3/3 0/0 x/2 1 -1/2; do
  "$exe" verify "$scene" "${plans[@]}" --shard "$v" --out "$work/badshard" > /dev/null 2> "$work/badshard.err"
  rc=$?
  [ $rc = 2 ] && grep -q -- "--shard" "$work/badshard.err" || bad "--shard $v: status $rc: $(cat "$work/badshard.err")"
done

# 4. mpirun -np 3 (one thread a rank): the single run's files, stdout and status.
if [ -n "$mpirun" ]; then
  "$mpirun" --oversubscribe --allow-run-as-root -np 3 "$exe" verify "$scene" --continuous --html "${plans[@]}" \
    --threads 1 --out "$work/mpi" --quiet > "$work/mpi.stdout" 2> "$work/mpi.err"
  echo $? > "$work/mpi.rc"
  grep -v ' plans, .* states, .* s (load' "$work/mpi.stdout" > "$work/mpi.out"
  same cont-single mpi
  python3 -c "import json,sys; r=json.load(open(sys.argv[1])); assert r['ranks']==3 and r['seconds']['chunks'], r" \
    "$work/mpi/report.json" || bad "the MPI report has no ranks or chunk times"
fi

[ $failures -eq 0 ] && echo "verify_distribute: all passed" && rm -rf "$work"
exit $((failures > 0))

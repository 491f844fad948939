#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs the libFuzzer targets of a fuzz build (make fuzz): each on a scratch
# copy of its seed corpus under tests/fuzz/corpus/<target>/, for its own time,
# at most JOBS targets at once (each libFuzzer process uses one core), the
# longest first, so the wall time is about the total time over JOBS.
# Any crash, sanitizer report, exception other than InputError, broken
# invariant, input slower than 10 s or over 2 GB fails; the input that did it
# is kept under BUILD/artifacts/, the log under BUILD/fuzz-<target>.log.
#
# usage: scripts/fuzz.sh BUILD JOBS TARGET=SECONDS...
set -uo pipefail
build=$1 jobs=$2
shift 2
top=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$build/artifacts"
build=$(cd "$build" && pwd)

# Longest first: a long target started last would leave the other lane idle.
mapfile -t order < <(for spec in "$@"; do echo "${spec#*=} ${spec%%=*}"; done | sort -rn)

run_one() {  # target seconds; prints one summary line, returns non-zero on failure
  local t=$1 secs=$2 work status
  work=$(mktemp -d)
  cp -r "$top/tests/fuzz/corpus/$t" "$work/corpus"
  # The targets' scratch files (tests/fuzz/support.h) go with $work: libFuzzer
  # ends its run without atexit handlers.
  mkdir "$work/tmp"
  TMPDIR="$work/tmp" "$build/fuzz/fuzz_$t" "$work/corpus" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" > "$build/fuzz-$t.log" 2>&1
  status=$?
  if [ $status -eq 0 ]; then
    echo "fuzz_$t: ok in $secs s, $(grep -h 'stat::number_of_executed_units' "$build/fuzz-$t.log" | awk '{print $2}') executions, corpus $(ls "$work/corpus" | wc -l) files"
  else
    echo "fuzz_$t: FAILED (log below, input in $build/artifacts/)"
    tail -n 60 "$build/fuzz-$t.log"
  fi
  rm -rf "$work"
  return $status
}

status=0
running=0
for entry in "${order[@]}"; do
  secs=${entry%% *} t=${entry#* }
  echo "fuzz_$t: $secs s on a copy of tests/fuzz/corpus/$t"
  # Each target's summary is written whole when it ends (no interleaving).
  run_one "$t" "$secs" > "$build/fuzz-$t.summary" 2>&1 &
  pids[$!]=$t
  running=$((running + 1))
  if [ $running -ge "$jobs" ]; then
    wait -n -p done_pid; rc=$?
    cat "$build/fuzz-${pids[$done_pid]}.summary"; [ $rc -eq 0 ] || status=1
    unset "pids[$done_pid]"; running=$((running - 1))
  fi
done
while [ $running -gt 0 ]; do
  wait -n -p done_pid; rc=$?
  cat "$build/fuzz-${pids[$done_pid]}.summary"; [ $rc -eq 0 ] || status=1
  unset "pids[$done_pid]"; running=$((running - 1))
done
exit $status

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# report.html for many candidate plans (issue 36), by hand, not in CI:
#   bench/report_page/many_plans.sh BUILD_DIR DATASET N WORK [extra verify options...]
# copies DATASET's plans into N files with distinct `# name:` lines, runs
# `verify` without and with --html (wall time and peak memory of each, from
# /usr/bin/time), prints the page's size, then opens the page in headless
# Chromium (tests/viewer/many_plans_test.mjs: its checks, the first render's
# time, a screenshot WORK/page.png). Timings are this machine's, under its load.
set -euo pipefail
build=$(realpath "$1"); data=$(realpath "$2"); n=$3; work=$4; shift 4
mkdir -p "$work"; work=$(realpath "$work")
bash "$(dirname "$0")/../../tests/viewer/copy_plans.sh" "$data/plans" "$n" "$work/plans"
run() {  # run NAME ARGS...: wall seconds and peak RSS (MB) of one verify
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$work/$name.time" "$build/plancheck" verify "$data/scene.json" "$work"/plans/*.csv \
    --quiet "$@" > /dev/null || [ $? -eq 1 ]
  read -r s kb < <(tail -n 1 "$work/$name.time")  # after "Command exited with non-zero status 1"
  echo "$name: $s s, $((kb / 1024)) MB peak"
}
run plain --out "$work/plain" "$@"
run html --out "$work/html" --html "$@"
echo "report.html: $(stat -c %s "$work/html/report.html") bytes; report.json: $(stat -c %s "$work/html/report.json") bytes"
node "$build/viewer/many_plans_test.mjs" --page "$work/html/report.html" --report "$work/html/report.json" \
  --shot "$work/page.png" --chromium "$(command -v chromium)"

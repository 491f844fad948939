#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# many_plans_pages.sh PLANCHECK DATASET N OUT HOSTILE: report.html of N
# copies of DATASET's plans (bench/report_page/copy_plans.sh), the first
# copy of plan04 (a collision) renamed HOSTILE (issue 31: a name that must
# not blank the page). ctest viewer.many_plans reads OUT/verify.
set -euo pipefail
plancheck=$1; data=$2; n=$3; out=$4; hostile=$5
here=$(dirname "$0")
rm -rf "$out"
bash "$here/copy_plans.sh" "$data/plans" "$n" "$out/plans"
victim=$(ls "$out"/plans/plan04_*.csv | head -n 1)
{ printf '# name: %s\n' "$hostile"; grep -v '^# name:' "$victim"; } > "$out/plans/hostile.csv"
rm "$victim"
"$plancheck" verify "$data/scene.json" "$out"/plans/*.csv --out "$out/verify" --html --quiet > /dev/null || [ $? -eq 1 ]

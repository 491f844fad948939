#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# copy_plans.sh FROM N TO (tests/viewer/many_plans_pages.sh, bench/report_page/many_plans.sh): the plans FROM/*.csv copied round-robin into N
# files TO/<plan>_<k>.csv, each with its own `# name:` line (<plan>_<k>).
set -euo pipefail
from=$1; n=$2; to=$3
rm -rf "$to"; mkdir -p "$to"
mapfile -t plans < <(ls "$from"/*.csv | sort)
for ((k = 0; k < n; ++k)); do
  src=${plans[k % ${#plans[@]}]}
  base=$(basename "$src" .csv)
  name="${base}_$((k / ${#plans[@]}))"
  sed "s/^# name: .*/# name: $name/" "$src" > "$to/$name.csv"
done

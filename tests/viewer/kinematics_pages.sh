#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# kinematics_pages.sh PLANCHECK OUT: report.html of tests/viewer/kinematics
# (every action type: a rotation about a tilted axis, a free translation
# and a scale composed on one part, a translation along a non-unit axis and
# a rotation on another; world objects attached to each and one in the world) for 60 plans of one random state each (the page carries the checker's transforms at a plan's closest state), some with
# angles of many whole turns (float64 parameters). ctest viewer.kinematics
# compares the page's poses with the checker's at those states.
set -euo pipefail
plancheck=$1; out=$2
here=$(dirname "$0")/kinematics
rm -rf "$out"; mkdir -p "$out/plans"
awk -v dir="$out/plans" 'BEGIN {
  srand(36);
  for (p = 0; p < 60; ++p) {
    f = sprintf("%s/k%02d.csv", dir, p);
    printf "# name: k%02d\nYaw,Shift.x,Shift.y,Shift.z,Grow.x,Grow.y,Grow.z,Boom,Pitch\n", p > f;
    big = (p % 4 == 3) ? 36000 : 0;
    for (s = 0; s < 1; ++s)
      printf "%.9g,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.9g\n", (rand() - 0.5) * 720 - big, rand() - 0.5, rand() - 0.5,
        rand() * 0.5, 0.5 + rand(), 0.5 + rand(), 0.5 + rand(), rand() - 0.5, (rand() - 0.5) * 360 + big > f;
    close(f);
  }
}'
"$plancheck" verify "$here/scene.json" "$out"/plans/*.csv --out "$out/verify" --html --html-plans 1000 --quiet > /dev/null || [ $? -eq 1 ]

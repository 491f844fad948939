# SPDX-License-Identifier: MIT
"""The Python module's per-call cost (issue 14) on the default plans.

    PYTHONPATH=build/python /usr/bin/python3 bench/api/python_overhead.py datasets/change5 [STATES]

Checks the first STATES states (default 1000) of the default plans one per
call and as one batch, on 1 and 2 threads; prints microseconds per state
(median of 5). plancheck_api_bench gives the C++ and verify numbers for the
same states and checks them against verify first; here the batch's answers
are checked against single calls before timing.
"""
import pathlib
import sys
import time

import numpy as np

import plancheck


def median(f, runs=5):
    t = []
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return sorted(t)[len(t) // 2]


def main():
    data = pathlib.Path(sys.argv[1])
    want = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    rows = []
    for plan in sorted((data / "plans").glob("*.csv")):
        lines = [l for l in plan.read_text().splitlines() if l.strip() and not l.startswith("#")]
        rows += [list(map(float, l.split(","))) for l in lines[1:]]
    states = np.array(rows[:want])
    n = len(states)
    one = plancheck.Scene(str(data / "scene.json"), threads=1)
    two = plancheck.Scene(str(data / "scene.json"), threads=2)
    batch = two.check(states)
    for i in range(0, n, 50):  # answers first
        r = one.check(states[i:i + 1])
        assert r.min_distance[0] == batch.min_distance[i] and r.verdict[0] == batch.verdict[i], i
    single = median(lambda: [one.check(states[i:i + 1]) for i in range(n)])
    b1 = median(lambda: one.check(states))
    b2 = median(lambda: two.check(states))
    us = lambda s: 1e6 * s / n
    print("%d states of the default plans (microseconds per state, median of 5)" % n)
    print("  Python scene.check, one state per call, 1 thread   %8.1f" % us(single))
    print("  Python scene.check(%d states), 1 thread          %8.1f" % (n, us(b1)))
    print("  Python scene.check(%d states), 2 threads         %8.1f" % (n, us(b2)))


if __name__ == "__main__":
    main()

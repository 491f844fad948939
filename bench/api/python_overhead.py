# SPDX-License-Identifier: MIT
"""The Python module's per-call cost (issue 14) on the default plans.

    PYTHONPATH=build/python /usr/bin/python3 bench/api/python_overhead.py datasets/change5 [STATES]

Checks the first STATES states (default 1000) of the default plans one per
call and as one batch, on 1 and 2 threads; prints microseconds per state
(median of 5). plancheck_api_bench gives the C++ and verify numbers for the
same states and checks them against verify first; here the batch's answers
are checked against single calls before timing.
"""
import json
import pathlib
import sys
import tempfile
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

    # The call itself: a two-box scene whose check costs about a microsecond,
    # so what a call adds shows above the machine's noise.
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        v = lambda lo, hi: "".join("v %g %g %g\n" % ((hi if i & 1 else lo)[0], (hi if i & 2 else lo)[1],
                                                       (hi if i & 4 else lo)[2]) for i in range(8))
        f = lambda b: "".join("f %d %d %d\n" % (b + x, b + y, b + z) for x, y, z in
                              [(1, 3, 2), (2, 3, 4), (5, 6, 7), (6, 8, 7), (1, 2, 5), (2, 6, 5),
                               (3, 7, 4), (4, 7, 8), (1, 5, 3), (3, 5, 7), (2, 4, 6), (4, 8, 6)])
        (folder / "model.obj").write_text("o Slab\n" + v((-3, -1, -1), (3, 1, 0)) + f(0) +
                                          "o Bar\n" + v((0, -0.1, 0.9), (2, 0.1, 1.1)) + f(8))
        (folder / "scene.json").write_text(json.dumps({
            "format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
            "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0]}],
            "safety_margin": 0.05}))
        tiny = plancheck.Scene(folder / "scene.json", threads=1)
        angles = np.linspace(-90, 20, n).reshape(-1, 1)
        t_single = median(lambda: [tiny.check(angles[i:i + 1]) for i in range(n)])
        t_batch = median(lambda: tiny.check(angles))
    print("two boxes (12 triangles each), %d states, 1 thread (microseconds per state)" % n)
    print("  Python scene.check, one state per call             %8.2f" % us(t_single))
    print("  Python scene.check(%d states)                    %8.2f" % (n, us(t_batch)))


if __name__ == "__main__":
    main()

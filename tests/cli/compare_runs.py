#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Compares two verify (or sweep) output folders as the contract asks: the
same file names (no file more, no file less), every file byte-identical
except report.json / sweep.json (and the JSON inside report.html /
sweep.html), which are equal once the
fields named seconds, threads, ranks and hosts are removed wherever they
appear. Also a no-terrain scene from a dataset (--no-terrain SCENE OUT).
Exit 0 when equal; otherwise prints the first difference, exit 1."""
import json
import os
import sys

TIMING = {"seconds", "threads", "ranks", "hosts"}
DATA_OPEN = '<script type="application/json" id="plancheck-data">'
CLOSE = "</script>"


def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if k not in TIMING}
    if isinstance(o, list):
        return [strip(v) for v in o]
    return o


def html_parts(path):
    text = open(path, encoding="utf-8").read()
    b = text.index(DATA_OPEN) + len(DATA_OPEN)
    e = text.index(CLOSE, b)
    return text[:b], strip(json.loads(text[b:e].replace("<\\/", "</"))), text[e:]


def compare(a, b):
    fa, fb = sorted(os.listdir(a)), sorted(os.listdir(b))
    if fa != fb:
        return f"files differ: {a}: {fa} / {b}: {fb}"
    for name in fa:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if name in ("report.json", "sweep.json"):
            if strip(json.load(open(pa))) != strip(json.load(open(pb))):
                return f"{name}: differs beyond the timing fields"
        elif name in ("report.html", "sweep.html"):
            if html_parts(pa) != html_parts(pb):
                return f"{name}: differs beyond the timing fields of its report"
        elif open(pa, "rb").read() != open(pb, "rb").read():
            return f"{name}: bytes differ"
    return None


def no_terrain(scene, out):
    s = json.load(open(scene))
    for k in ("terrain", "scoop", "probes"):
        s.pop(k, None)
    s["model"] = os.path.join(os.path.dirname(os.path.abspath(scene)), s["model"])
    s["allowed_collisions"] = [p for p in s.get("allowed_collisions", []) if "terrain" not in json.dumps(p)]
    json.dump(s, open(out, "w"), indent=1)


if __name__ == "__main__":
    if sys.argv[1] == "--no-terrain":
        no_terrain(sys.argv[2], sys.argv[3])
        sys.exit(0)
    why = compare(sys.argv[1], sys.argv[2])
    if why:
        print(f"compare_runs: {sys.argv[1]} vs {sys.argv[2]}: {why}")
        sys.exit(1)

#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# install_in_venv.sh PYTHON SOURCE BUILD VENV VERSION (ctest python.install)
# A fresh `PYTHON -m venv --system-site-packages VENV`, then, offline, as the
# README says: `pip install --no-build-isolation SOURCE` and
# `python3 -m build --wheel --no-isolation SOURCE`, both taking the module
# the CMake folder BUILD built (PLANCHECK_CMAKE_BUILD_DIR, setup.py). Checks
# what the wheel holds. Fails on the first thing wrong.
set -euo pipefail
python=$1 source=$2 build=$3 venv=$4 version=$5
rm -rf "$venv"
# --without-pip: the venv's python runs Debian's pip from the system site
# (the same pip 23 that ensurepip would copy in, minus a few seconds).
"$python" -m venv --system-site-packages --without-pip "$venv"
export PLANCHECK_CMAKE_BUILD_DIR=$build PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1
cd "$venv"   # not the source tree: nothing found there by accident
"$venv/bin/python" -m pip install --quiet --no-build-isolation "$source"
"$venv/bin/python" -m build --wheel --no-isolation --outdir "$venv/dist" "$source" > "$venv/build.log" ||
  { cat "$venv/build.log"; exit 1; }
"$venv/bin/python" - "$venv/dist" "$version" <<'PY'
import pathlib, sys, sysconfig, zipfile
dist, version = pathlib.Path(sys.argv[1]), sys.argv[2]
wheels = list(dist.glob("*.whl"))
assert len(wheels) == 1, wheels
assert wheels[0].name.startswith("plancheck-%s-" % version), wheels[0].name
names = sorted(n for n in zipfile.ZipFile(wheels[0]).namelist() if not n.startswith("plancheck-%s.dist-info/" % version))
expect = sorted("plancheck/" + f for f in ("__init__.py", "_plancheck.pyi", "py.typed",
                                          "_plancheck" + sysconfig.get_config_var("EXT_SUFFIX")))
assert names == expect, "wheel holds %s, expected %s" % (names, expect)
meta = zipfile.ZipFile(wheels[0]).read("plancheck-%s.dist-info/METADATA" % version).decode()
for line in ("Requires-Dist: numpy", "Requires-Python: >=3.9", "Version: " + version):
    assert line in meta.splitlines(), "METADATA lacks %r" % line
print("venv %s: pip install and the wheel %s (%s)" % (sys.prefix, wheels[0].name, ", ".join(names)))
PY

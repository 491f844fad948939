# SPDX-License-Identifier: MIT
"""The Python package `plancheck` gives `plancheck verify`'s per-state answers.

Run by ctest (tests/python/CMakeLists.txt) with the python of a venv the
package was pip-installed into (python.install) and PLANCHECK_BINARY_DIR
set; every answer is compared with the CSV rows and the report.json
verdicts that verify writes for the same states. PackageTest checks the
installed package itself: where it is, NumPy missing, its types.
"""
import csv
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import threading
import unittest

import numpy as np

import plancheck

BINARY = pathlib.Path(os.environ.get("PLANCHECK_BINARY_DIR", "build"))
VERDICTS = {0: "safe", 1: "clearance", 2: "collision", 3: "limits"}


def verify(scene, plans, out, *options):
    """Runs `plancheck verify --quiet`; returns (status, stderr)."""
    p = subprocess.run([str(BINARY / "plancheck"), "verify", str(scene), *map(str, plans),
                        "--out", str(out), "--quiet", *options],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return p.returncode, p.stderr


def num(v):
    """verify's CSV number format (src/report.cpp)."""
    return "" if not math.isfinite(v) else "%.12g" % v


def box(name, lo, hi, base):
    v = [(hi if i & 1 else lo)[0:1] + (hi if i & 2 else lo)[1:2] + (hi if i & 4 else lo)[2:3] for i in range(8)]
    faces = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
             (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    text = "o %s\n" % name + "".join("v %r %r %r\n" % tuple(p) for p in v)
    return text + "".join("f %d %d %d\n" % tuple(base + i + 1 for i in f) for f in faces)


def write_bar_scene(folder, scale=1.0, unit="m"):
    """The stiff case of tests/api: a 2-unit bar pitching 1 unit above a slab."""
    s = lambda *xs: [x * scale for x in xs]
    (folder / "model.obj").write_text(box("Slab", s(-3, -1, -1), s(3, 1, 0), 0) +
                                      box("Bar", s(0, -0.1, 0.9), s(2, 0.1, 1.1), 8))
    (folder / "scene.json").write_text(json.dumps({
        "format": "plancheck-scene/1", "model": "model.obj", "length_unit": unit, "angle_unit": "deg",
        "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": s(0, 0, 1),
                     "axis": [0, 1, 0], "limits": [-90, 30]}],
        "safety_margin": 0.05 * scale}))
    return folder / "scene.json"


# Degrees as written: far, around the margin (25.458364447446368), around
# contact (27.096330350410646), in contact, beyond the limits.
BAR_ANGLES = [-90.0, -45.0, 0.0, 10.0, 25.45836444744637 - 1e-6, 25.458364447446368,
              25.45836444744637 + 1e-6, 27.096330350410646 - 1e-7, 27.096330350410646,
              27.1, 29.99, 30.000001, 390.0, -330.0, 720.0]


def expect_rows(test, result, rows, where, tie_points=False):
    """The check result against verify's CSV rows, state by state. Closest
    points are not unique where faces are parallel at the minimum, and verify
    seeds a state's search with the previous state's pair: with tie_points,
    points that differ from verify's must be as far apart as min_distance,
    as verify's are. Returns how many states had such tied points."""
    test.assertEqual(len(rows), len(result))
    tied = 0
    for s, row in enumerate(rows):
        at = "%s state %d" % (where, s)
        test.assertEqual(row["collision"], "1" if result.collision[s] else "0", at)
        test.assertEqual(row["min_distance"], num(result.min_distance[s]), at)
        a, b = result.part_a[s], result.part_b[s]
        test.assertEqual(row["part_a"], result.part_names[a] if a >= 0 else "", at)
        test.assertEqual(row["part_b"], result.part_names[b] if b >= 0 else "", at)
        mine = [num(result.point_a[s, k]) if a >= 0 else "" for k in range(3)] + \
               [num(result.point_b[s, k]) if a >= 0 else "" for k in range(3)]
        theirs = [row[c] for c in ("ax", "ay", "az", "bx", "by", "bz")]
        if mine == theirs:
            continue
        test.assertTrue(tie_points and a >= 0, "%s: points %s, verify %s" % (at, mine, theirs))
        d = result.min_distance[s]
        tol = 1e-9 * max(1.0, d)
        test.assertAlmostEqual(np.linalg.norm(result.point_a[s] - result.point_b[s]), d, delta=tol, msg=at)
        v = np.array(list(map(float, theirs)))
        test.assertAlmostEqual(np.linalg.norm(v[:3] - v[3:]), d, delta=tol, msg=at)
        tied += 1
    return tied


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class PackageTest(unittest.TestCase):
    def test_imported_from_the_venv(self):
        """The installed package, not the source tree or build/python."""
        self.assertNotEqual(sys.prefix, sys.base_prefix, "not run in a venv")
        where = pathlib.Path(plancheck.__file__).resolve()
        self.assertTrue(where.is_relative_to(pathlib.Path(sys.prefix).resolve()), where)
        for f in ("_plancheck.pyi", "py.typed"):
            self.assertTrue((where.parent / f).is_file(), f)
        self.assertEqual(repr(plancheck.Error), "<class 'plancheck.Error'>")

    def test_without_numpy_import_fails_at_once(self):
        """With no site packages (python -S) NumPy is really missing while the
        installed package is on the path: import raises, saying what is missing."""
        site = str(pathlib.Path(plancheck.__file__).parent.parent)
        run = lambda code: subprocess.run([sys.executable, "-S", "-c", "import sys; sys.path.insert(0, %r); %s" % (site, code)],
                                          capture_output=True, text=True)
        self.assertIn("No module named 'numpy'", run("import numpy").stderr)
        p = run("import plancheck")
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("ImportError: plancheck needs NumPy, which %s cannot import" % sys.executable, p.stderr)
        self.assertIn("apt-get install python3-numpy", p.stderr)

    def test_types_seen_by_mypy_strict(self):
        """mypy --strict (one run, both files): typed_example.py is clean; each
        line of typed_wrong.py marked `# wrong` is flagged, and no other."""
        p = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-error-summary",
                            "typed_example.py", "typed_wrong.py"],
                           capture_output=True, text=True, cwd=pathlib.Path(__file__).parent)
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        errors = [line for line in p.stdout.splitlines() if ": error:" in line]
        self.assertEqual([e for e in errors if not e.startswith("typed_wrong.py:")], [], p.stdout)
        wrong = pathlib.Path(__file__).with_name("typed_wrong.py").read_text().splitlines()
        expected = [i + 1 for i, line in enumerate(wrong) if line.rstrip().endswith("# wrong")]
        flagged = sorted(set(int(e.split(":")[1]) for e in errors))
        self.assertEqual(flagged, expected, p.stdout)

    def test_stubs_match_the_module(self):
        """mypy.stubtest: every name and signature of _plancheck.pyi against the built module."""
        allowlist = pathlib.Path(__file__).with_name("stubtest_allowlist.txt")
        with tempfile.TemporaryDirectory() as tmp:  # stubtest writes .mypy_cache where it runs
            p = subprocess.run([sys.executable, "-m", "mypy.stubtest", "plancheck", "--allowlist", str(allowlist)],
                               capture_output=True, text=True, cwd=tmp)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)


class ModuleTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def test_version(self):
        self.assertEqual(plancheck.__version__, os.environ["PLANCHECK_VERSION"])
        out = subprocess.run([str(BINARY / "plancheck"), "--version"], capture_output=True, text=True, check=True)
        self.assertEqual(out.stdout, "plancheck %s\n" % plancheck.__version__)

    def check_bar(self, scale, unit):
        scene_file = write_bar_scene(self.dir, scale, unit)
        plans = []
        for i, a in enumerate(BAR_ANGLES):  # one plan per state: report.json's verdict is the state's
            plans.append(self.dir / ("s%03d.csv" % i))
            plans[-1].write_text("J1\n%r\n" % a)
        status, _ = verify(scene_file, plans, self.dir / "out")
        self.assertEqual(status, 1)
        report = json.loads((self.dir / "out" / "report.json").read_text())

        scene = plancheck.Scene(scene_file, threads=2)  # a pathlib.Path or a str
        self.assertEqual(scene.parameter_names, ["J1"])
        self.assertEqual(scene.length_unit, unit)
        states = np.array(BAR_ANGLES).reshape(-1, 1)
        r = scene.check(states)
        self.assertEqual(r.collision.dtype, np.bool_)
        self.assertEqual(r.min_distance.dtype, np.float64)
        self.assertEqual(r.verdict.dtype, np.uint8)
        rows = [read_rows(self.dir / "out" / ("s%03d.csv" % i))[0] for i in range(len(BAR_ANGLES))]
        expect_rows(self, r, rows, unit)
        self.assertEqual([VERDICTS[int(v)] for v in r.verdict], [p["verdict"] for p in report["plans"]])
        self.assertEqual(set(int(v) for v in r.verdict), {0, 1, 2, 3})
        # verdict_only: the same verdicts; exact distances below the margin,
        # elsewhere exact or a certified lower bound (then no pair named).
        v = scene.check(states, verdict_only=True)
        np.testing.assert_array_equal(v.verdict, r.verdict)
        np.testing.assert_array_equal(v.collision, r.collision)
        self.assertFalse(r.min_distance_is_bound.any())
        below = r.min_distance < scene.safety_margin
        np.testing.assert_allclose(v.min_distance[below], r.min_distance[below], rtol=0, atol=1e-12 * scale)
        self.assertFalse(v.min_distance_is_bound[below].any())
        bound = v.min_distance_is_bound
        self.assertTrue(bound.any())  # the far states need no exact distance
        self.assertTrue((v.min_distance[bound] <= r.min_distance[bound] + 1e-12 * scale).all())
        self.assertTrue((v.min_distance[bound] >= scene.safety_margin).all())
        self.assertTrue((v.part_a[bound] == -1).all())
        # One state per call gives the batch's answers.
        for i in range(len(BAR_ANGLES)):
            one = scene.check(states[i:i + 1])
            self.assertEqual(one.min_distance[0], r.min_distance[i])
            self.assertEqual(one.verdict[0], r.verdict[i])

    def test_stiff_bar_equals_verify(self):
        self.check_bar(1.0, "m")

    def test_stiff_bar_in_millimetres_equals_verify(self):
        self.check_bar(1000.0, "mm")

    def test_bad_scene_raises_verifys_message(self):
        scene_file = write_bar_scene(self.dir)
        (self.dir / "plan.csv").write_text("J1\n0\n")
        good = scene_file.read_text()
        cases = {"missing.json": None, "bad-json.json": '{"format": ',
                 "bad-margin.json": good.replace('"safety_margin": 0.05', '"safety_margin": -1'),
                 "bad-model.json": good.replace("model.obj", "nothing.obj")}
        for name, text in cases.items():
            path = self.dir / name
            if text is not None:
                path.write_text(text)
            status, err = verify(path, [self.dir / "plan.csv"], self.dir / "out")
            self.assertEqual(status, 2, name)
            with self.assertRaises(plancheck.Error) as caught:
                plancheck.Scene(str(path))
            self.assertEqual("plancheck: %s\n" % caught.exception, err, name)
            self.assertIsInstance(caught.exception, ValueError)

    def test_world_objects_at_run_time(self):
        # The same objects in the scene file and added at run time give the
        # same answers; a moved object is seen at its new pose only; errors
        # raise plancheck.Error (a ValueError) naming the object and field.
        plain = write_bar_scene(self.dir)
        text = json.loads(plain.read_text())
        text["objects"] = [
            {"name": "Rock", "box": [0.2, 0.4, 0.2], "pose": {"xyz": [1, 0, 1.35], "rpy": [0, 0, 30]}},
            {"name": "Ball", "sphere": 0.1, "pose": {"xyz": [1.5, 0, 0.5]}},
            {"name": "Pole", "cylinder": {"radius": 0.05, "length": 1.2}, "pose": {"xyz": [-1, 0.4, 0.6]}},
            {"name": "Tag", "box": [0.1, 0.1, 0.1], "parent": "Bar", "pose": {"xyz": [1, 0, 0.5]}}]
        with_objects = self.dir / "objects.json"
        with_objects.write_text(json.dumps(text))
        json_scene = plancheck.Scene(with_objects, threads=1)
        run = plancheck.Scene(plain, threads=1)
        run.add_object("Rock", box=[0.2, 0.4, 0.2], pose=((1, 0, 1.35), (0, 0, 30)))
        run.add_object("Ball", sphere=0.1, pose=((1.5, 0, 0.5), (0, 0, 0)))
        run.add_object("Pole", cylinder=(0.05, 1.2), pose=((-1, 0.4, 0.6), (0, 0, 0)))
        run.add_object("Tag", box=(0.1, 0.1, 0.1), pose=((1, 0, 0.5), (0, 0, 0)), parent="Bar")
        self.assertEqual(run.object_names, ["Rock", "Ball", "Pole", "Tag"])
        self.assertEqual(run.object_names, json_scene.object_names)
        states = np.linspace(-90, 30, 121)
        a, b = json_scene.check(states.reshape(-1, 1)), run.check(states.reshape(-1, 1))
        np.testing.assert_array_equal(a.min_distance, b.min_distance)
        np.testing.assert_array_equal(a.verdict, b.verdict)
        self.assertEqual(a.part_b_names, b.part_b_names)
        self.assertIn("Ball", a.part_b_names)
        # The bar at 0 degrees: Rock 0.15 above it is the closest part; moved
        # 0.35 higher, Ball (about 0.3 below the bar) is.
        before = run.check([0.0])
        self.assertEqual(before.part_b_names, ["Rock"])
        run.move_object("Rock", ((1, 0, 1.7), (0, 0, 30)))
        self.assertEqual(run.check([0.0]).part_b_names, ["Ball"])
        run.move_object("Rock", ((1, 0, 1.35), (0, 0, 30)))
        self.assertAlmostEqual(run.check([0.0]).min_distance[0], before.min_distance[0], delta=1e-12)
        run.remove_object("Rock")
        self.assertEqual(run.object_names, ["Ball", "Pole", "Tag"])
        for call, message in (
                (lambda: run.add_object("Ball", sphere=1.0), "'Ball' is already"),
                (lambda: run.add_object("X", sphere=-1.0), r"objects\['X'\]\.sphere: must be a positive"),
                (lambda: run.add_object("X", sphere=1.0, box=[1, 1, 1]), "exactly one of"),
                (lambda: run.add_object("X", sphere=1.0, parent="Nowhere"), "no node or link named 'Nowhere'"),
                (lambda: run.add_object("X", mesh=self.dir / "missing.stl"), r"mesh: cannot open"),
                (lambda: run.move_object("Rock", ((0, 0, 0), (0, 0, 0))), "no object named 'Rock'"),
                (lambda: run.remove_object("Slab"), "no object named 'Slab'")):
            with self.assertRaisesRegex(ValueError, message):
                call()

    def test_shape_errors_raise(self):
        scene = plancheck.Scene(str(write_bar_scene(self.dir)), threads=1)
        for bad in (np.zeros(3), np.zeros((2, 2)), np.zeros((1, 1, 1)), [["a"]]):
            with self.assertRaises(plancheck.Error, msg=repr(bad)):
                scene.check(bad)
        with self.assertRaisesRegex(plancheck.Error, "state 1: parameter 'J1' is not a finite number"):
            scene.check(np.array([[0.0], [np.nan]]))
        self.assertEqual(len(scene.check(np.zeros((0, 1)))), 0)
        # Lists and integer arrays are converted (plan units as written).
        self.assertEqual(scene.check([[0], [10]]).verdict.tolist(), [0, 0])

    def test_threads_agree_and_run_without_the_gil(self):
        scene_file = str(write_bar_scene(self.dir))
        states = np.linspace(-90, 40, 400).reshape(-1, 1)
        one = plancheck.Scene(scene_file, threads=1).check(states)
        scene = plancheck.Scene(scene_file, threads=2)
        results = [None] * 4

        def work(i):
            results[i] = scene.check(states)
        pool = [threading.Thread(target=work, args=(i,)) for i in range(4)]
        for t in pool:
            t.start()
        for t in pool:
            t.join()
        for r in results:
            np.testing.assert_array_equal(r.min_distance, one.min_distance)
            np.testing.assert_array_equal(r.verdict, one.verdict)
            np.testing.assert_array_equal(r.point_a, one.point_a)


    def test_read_plan(self):
        scene = plancheck.Scene(write_bar_scene(self.dir), threads=1)
        plan = self.dir / "p.csv"
        plan.write_text('# name: x\ntime,"J1"\n0,10\n1.5,-20.5\n2,1e300\n')
        states = scene.read_plan(plan)
        self.assertEqual(states.shape, (3, 1))
        self.assertEqual(states[:, 0].tolist(), [10.0, -20.5, 1e300])
        bad = self.dir / "bad.csv"
        bad.write_text("J1\n0\nfive\n")
        with self.assertRaisesRegex(plancheck.Error, "bad.csv:3:1: column 'J1': 'five' is not a finite number"):
            scene.read_plan(str(bad))

    def test_limits_one_state_and_complex_values(self):
        scene_file = write_bar_scene(self.dir)
        scene = plancheck.Scene(scene_file, threads=1)
        for limits, value in ((scene.lower_limits, -90.0), (scene.upper_limits, 30.0)):
            self.assertIsInstance(limits, np.ndarray)
            self.assertEqual(limits.dtype, np.float64)
            self.assertEqual(limits.tolist(), [value])
        unlimited = self.dir / "unlimited.json"
        unlimited.write_text(scene_file.read_text().replace(', "limits": [-90, 30]', ""))
        free = plancheck.Scene(unlimited, threads=1)
        self.assertEqual(free.lower_limits.tolist(), [-math.inf])
        self.assertEqual(free.upper_limits.tolist(), [math.inf])
        # A 1-D array of len(parameter_names) values is one state.
        one = scene.check(np.array([27.1]))
        two = scene.check(np.array([[27.1]]))
        self.assertEqual(len(one), 1)
        self.assertEqual(one.verdict.tolist(), two.verdict.tolist())
        self.assertEqual(one.min_distance.tolist(), two.min_distance.tolist())
        m = scene.check_motion([0.0], [29.0])
        self.assertEqual(len(m), 1)
        self.assertEqual(m.verdict.tolist(), [2])
        # Complex states are refused, not cast (the imaginary part dropped).
        for bad in (np.array([[1 + 2j]]), np.array([[1 + 0j]]), [[1 + 2j]], np.array([5j])):
            with self.assertRaisesRegex(plancheck.Error, "complex", msg=repr(bad)):
                scene.check(bad)
            with self.assertRaisesRegex(plancheck.Error, "complex", msg=repr(bad)):
                scene.check_motion(bad, [[0.0]])
        with self.assertRaisesRegex(plancheck.Error, "same number"):
            scene.check_motion(np.zeros((2, 1)), np.zeros((3, 1)))

    def test_check_motion_equals_verify_continuous(self):
        """Every motion between two stiff bar states (near misses, whole
        turns written as 390, -330, 720) against verify --continuous on the
        same two-state plan."""
        scene_file = write_bar_scene(self.dir)
        angles = BAR_ANGLES[::2] + [25.45836444744637 + 1e-9]
        starts, ends, plans = [], [], []
        for a in angles:
            for b in angles:
                starts.append([a])
                ends.append([b])
                plans.append(self.dir / ("m%04d.csv" % len(plans)))
                plans[-1].write_text("J1\n%r\n%r\n" % (a, b))
        status, err = verify(scene_file, plans, self.dir / "out", "--continuous")
        self.assertLessEqual(status, 1, err)
        report = json.loads((self.dir / "out" / "report.json").read_text())
        scene = plancheck.Scene(scene_file, threads=2)
        full = scene.check_motion(np.array(starts), np.array(ends))
        quick = scene.check_motion(np.array(starts), np.array(ends), verdict_only=True)
        valid = scene.check_motion(np.array(starts), np.array(ends), verdict_only=True, first_violation=True)
        ends_checked = scene.check(np.array(ends))
        self.assertEqual(full.t.dtype, np.float64)
        for i, plan in enumerate(report["plans"]):
            where = "motion %r -> %r" % (starts[i][0], ends[i][0])
            with open(self.dir / "out" / (plans[i].stem + ".csv"), newline="") as f:
                row = list(csv.DictReader(f))[0]
            for r in (full, quick):
                self.assertEqual(VERDICTS[int(r.verdict[i])], plan["verdict"], where)
                self.assertEqual(bool(r.collision[i]), row["segment_collision"] == "1", where)
                first = plan["first_violation"]
                if first is None:
                    self.assertTrue(math.isnan(r.t[i]), where)
                elif first.get("between"):
                    self.assertEqual(num(r.t[i]), row["segment_t"], where)
                else:
                    self.assertEqual(r.t[i], float(first["state"]), where)
            self.assertEqual(num(full.min_distance[i]), row["segment_min_distance"], where)
            self.assertLessEqual(quick.min_distance[i], full.min_distance[i], where)
            # first_violation: safe exactly where verify says so; a motion
            # found below the margin is a clearance there (no contact pass).
            self.assertEqual(valid.verdict[i] == 0, plan["verdict"] == "safe", where)
            if plan["verdict"] == "safe":
                self.assertEqual(valid.min_distance[i], quick.min_distance[i], where)
            elif plan["first_violation"].get("between"):
                # The margin pass's witness: state 1 touching, else a clearance.
                touch = valid.t[i] == 1.0 and bool(ends_checked.collision[i])
                self.assertEqual(VERDICTS[int(valid.verdict[i])], "collision" if touch else "clearance", where)
                self.assertEqual(bool(valid.collision[i]), bool(ends_checked.collision[i]), where)
                if ends_checked.collision[i]:
                    self.assertEqual(valid.min_distance[i], 0.0, where)
                else:
                    self.assertTrue(math.isnan(valid.min_distance[i]), where)
                if row["segment_collision"] == "0":
                    self.assertEqual(valid.t[i], quick.t[i], where)
        self.assertEqual(set(full.verdict.tolist()), {0, 1, 2, 3})


class DatasetTest(unittest.TestCase):
    def test_default_plans_equal_verify(self):
        """Every state of the default plans. verify digs along a plan; the
        module checks on the initial terrain, so verify runs on the scene
        without its scoop block (nothing dug), the module on the original."""
        data = BINARY / "test-dataset"
        self.assertTrue((data / "scene.json").exists(), "run DatasetFixture.Generate")
        plans = sorted((data / "plans").glob("*.csv"))
        with tempfile.TemporaryDirectory() as tmp:
            spec = json.loads((data / "scene.json").read_text())
            del spec["scoop"]
            # In the temporary directory, the model and the DEM named by
            # absolute paths: nothing is written beside the dataset.
            spec["model"] = str((data / spec["model"]).resolve())
            spec["terrain"]["dem"] = str((data / spec["terrain"]["dem"]).resolve())
            nodig = pathlib.Path(tmp) / "scene-nodig.json"
            nodig.write_text(json.dumps(spec))
            status, err = verify(nodig, plans, pathlib.Path(tmp) / "out")
            self.assertLessEqual(status, 1, err)
            report = json.loads((pathlib.Path(tmp) / "out" / "report.json").read_text())
            scene = plancheck.Scene(str(data / "scene.json"))
            total = 0
            for plan_file, plan in zip(plans, report["plans"]):
                with open(plan_file, newline="") as f:
                    lines = [l for l in f if not l.startswith("#") and l.strip()]
                header = lines[0].strip().split(",")
                self.assertEqual(header, scene.parameter_names)
                states = scene.read_plan(plan_file)
                self.assertEqual(states.dtype, np.float64)
                np.testing.assert_array_equal(states, np.loadtxt(lines[1:], delimiter=",", ndmin=2), plan["name"])
                r = scene.check(states)
                expect_rows(self, r, read_rows(pathlib.Path(tmp) / "out" / (plan["name"] + ".csv")), plan["name"],
                            tie_points=True)
                v = scene.check(states, verdict_only=True)
                np.testing.assert_array_equal(v.verdict, r.verdict, plan["name"])
                bad = np.flatnonzero(r.verdict != 0)
                fv = plan["first_violation"]
                if len(bad):
                    self.assertEqual(fv["state"], int(bad[0]), plan["name"])
                    self.assertEqual(fv["kind"], VERDICTS[int(r.verdict[bad[0]])], plan["name"])
                else:
                    self.assertTrue(fv is None or fv["kind"] == "target", plan["name"])
                total += len(states)
            self.assertGreater(total, 2000)


if __name__ == "__main__":
    unittest.main()

# SPDX-License-Identifier: MIT
"""The API as a typed caller uses it: `mypy --strict` must accept this file
against the installed package's stubs (tests/python PackageTest). Not run."""
import numpy as np
import numpy.typing as npt

import plancheck


def first_violations(scene: plancheck.Scene, states: npt.NDArray[np.float64]) -> list[tuple[int, str, str]]:
    r: plancheck.CheckResult = scene.check(states)
    verdicts: npt.NDArray[np.uint8] = r.verdict
    distances: npt.NDArray[np.float64] = r.min_distance
    out = []
    for i in np.flatnonzero(verdicts != 0):
        a, b = r.part_a_names[i], r.part_b_names[i]
        out.append((int(i), a or "", b or "%.3f" % float(distances[i])))
    return out


def main() -> None:
    print(plancheck.__version__)
    try:
        scene = plancheck.Scene("scene.json", threads=2, srdf=None, packages={"arm": "meshes"})
    except plancheck.Error as e:
        print("plancheck: %s" % e)
        return
    names: list[str] = scene.parameter_names
    states = np.zeros((4, len(names)))
    print(first_violations(scene, states), scene.part_names, scene.safety_margin + 1.0,
          scene.length_unit.upper(), scene.angle_unit, scene.threads, sum(scene.reference_state))
    v = scene.check([[0.0] * len(names)], verdict_only=True)
    bound: npt.NDArray[np.bool_] = v.min_distance_is_bound
    points: npt.NDArray[np.float64] = v.point_a - v.point_b
    parts: npt.NDArray[np.int32] = v.part_a
    print(len(v), bound.any(), points.shape, parts, v.part_b, v.collision, v.point_b, v.part_names)
    scene.add_object("Rock", box=[0.3, 0.2, 0.15], pose=((2.9, 0.1, 0.07), (0.0, 0.0, 30.0)))
    scene.add_object("Bag", sphere=0.05, pose=((0, 0, 0.06), (0, 0, 0)), parent="Scoop")
    scene.add_object("Pole", cylinder=(0.05, 1.2))
    scene.add_object("Crate", mesh="crate.stl", scale=(1, 1, 1))
    scene.move_object("Rock", ((3.0, 0.1, 0.07), (0.0, 0.0, 45.0)))
    scene.remove_object("Rock")
    objects: list[str] = scene.object_names
    print(objects)


if __name__ == "__main__":
    main()

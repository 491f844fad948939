# SPDX-License-Identifier: MIT
"""Misuses `mypy --strict` must catch through the stubs, one on each line
marked `# wrong` (tests/python PackageTest checks exactly those lines). Not run."""
import numpy as np

import plancheck

scene = plancheck.Scene("scene.json", threads="2")  # wrong
scene.check(np.zeros((1, 4)), verdict_only="yes")  # wrong
r = scene.check(np.zeros((1, 4)))
name: int = scene.parameter_names[0]  # wrong
unit: float = scene.length_unit  # wrong
part: str = r.part_a_names[0]  # wrong
scene.check_states(np.zeros((1, 4)))  # wrong
scene.safety_margin = 0.1  # wrong
plancheck.Scene("scene.json", packages={"arm": 3})  # wrong

# SPDX-License-Identifier: MIT
"""plancheck: check robot-arm states against a scene with the answers of `plancheck verify`.

    import numpy as np, plancheck
    scene = plancheck.Scene("scene.json")          # or a .urdf; raises plancheck.Error
    r = scene.check(np.zeros((1, len(scene.parameter_names))))
    r.verdict, r.min_distance, r.part_a_names

The compiled part is plancheck._plancheck; the types are in _plancheck.pyi.
"""


def _require_numpy() -> None:
    """The results are NumPy arrays: without NumPy the compiled module would
    load and fail only at the first check, so say so at import."""
    import sys
    try:
        import numpy  # noqa: F401
    except ImportError as e:
        raise ImportError(
            "plancheck needs NumPy, which %s cannot import (%s): install it "
            "(Debian: apt-get install python3-numpy; in a venv: pip install numpy)" % (sys.executable, e)
        ) from e


_require_numpy()

from ._plancheck import CheckResult, Error, MotionResult, Scene, __version__  # noqa: E402

# Shown as plancheck.Scene, plancheck.Error ... in reprs and tracebacks.
for _t in (CheckResult, Error, MotionResult, Scene):
    _t.__module__ = __name__
del _t

__all__ = ["CheckResult", "Error", "MotionResult", "Scene", "__version__"]

"""Helpers of the robot tests: the example URDF, copies of it with one slip, and
MuJoCo's whole-robot inertia as the oracle of the MJCF tests."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from tumble.robots import example_path

#: The example URDF (a base, an arm and a hand), as written.
EXAMPLE = example_path().read_text(encoding="utf-8")


def robot_file(tmp_path: Path, text: str = EXAMPLE, name: str = "arm.urdf") -> Path:
    """``text`` written (UTF-8) as ``name`` in ``tmp_path``."""
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def slipped(tmp_path: Path, old: str, new: str, name: str = "arm.urdf") -> Path:
    """The example with ``old`` (which it holds) written as ``new``."""
    assert old in EXAMPLE
    return robot_file(tmp_path, EXAMPLE.replace(old, new), name)


def mujocos_inertia(model: Any, data: Any, centre: np.ndarray) -> np.ndarray:
    """Oracle: the whole robot's inertia about ``centre`` (m, world frame), kg·m², in
    world axes, from MuJoCo's compiled model after ``mj_kinematics``: each body's
    ``body_inertia`` turned by its ``ximat`` and moved from its ``xipos`` to
    ``centre`` (parallel axes), summed."""
    inertia = np.zeros((3, 3))
    for i in range(1, model.nbody):
        rotation = data.ximat[i].reshape(3, 3)
        d = data.xipos[i] - centre
        inertia += rotation @ np.diag(model.body_inertia[i]) @ rotation.T + model.body_mass[i] * (
            d @ d * np.eye(3) - np.outer(d, d)
        )
    return inertia

"""Rotordynamics: a rigid rotor on elastic bearings, its closed forms and its run-up,
in one namespace.

* ``RigidRotor`` on ``Bearing`` objects — a rigid rotor (the body, a solid of
  revolution about its spin axis) on elastic, damped bearings: its whirl
  frequencies and modes (``Whirl``, the Campbell diagram), its critical speeds
  and its unbalance response, in closed form: the same objects as
  :class:`tumble.theory.RigidRotor`, :class:`tumble.theory.Bearing` and
  :class:`tumble.theory.Whirl`, documented there.
* ``run_up`` → ``RunUp`` — the rotor run up (or held at one speed) with an
  unbalance, integrated in time by a compiled Runge–Kutta kernel
  (``tumble.core.whirl``): its bearing orbits through the critical speeds; the
  same objects as :func:`tumble.models.run_up` and :class:`tumble.models.RunUp`.

A scenario file's ``[rotordynamics]`` table runs both and compares them (``tumble
show rotor-on-bearings``). Not to be confused with the ``rotor`` part of
:mod:`tumble.parts`, a wheel spinning inside a free body, nor with
:func:`tumble.theory.rotor_loads`, the loads a body turned at a steady rate puts
on its shaft's bearings.

References: Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines*, 2010,
§3.5–3.6; Genta, *Dynamics of Rotating Systems*, 2005, ch. 3.
"""

from __future__ import annotations

from tumble.models.run_up import RunUp, run_up
from tumble.theory.rotordynamics import Bearing, RigidRotor, Whirl

__all__ = ["Bearing", "RigidRotor", "RunUp", "Whirl", "run_up"]

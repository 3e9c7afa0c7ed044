"""Physics engines against the exact answer: how MuJoCo, PyBullet, Drake, DART, Rapier,
scipy's ODE solvers and tumble's own integrators turn a rotating rigid body.

Each engine is an adapter in a registry (:data:`ENGINES`, :func:`register_engine`),
installed with the optional extra ``tumble[engines]``; a missing one is skipped
with a note. :func:`run` steps every engine on a :class:`Scenario` whose exact
motion tumble knows in closed form and measures energy, momentum, attitude and
angular-velocity errors, flips and failures; :func:`sweep` adds each engine's
observed order of convergence and largest safe step.

Examples
--------
>>> import tumble as tb
>>> result = tb.conformance.run(["mujoco/rk4", "tumble/rk4"], "major-spin", dt=1e-3, duration=1.0)
>>> list(result.table["engine"])
['mujoco/rk4', 'tumble/rk4']
"""

from tumble.conformance import engines  # noqa: F401 - registers the built-in adapters
from tumble.conformance.engine import (
    ENGINES,
    EXTRA,
    Engine,
    EngineBody,
    Samples,
    engine_names,
    register_engine,
)
from tumble.conformance.running import (
    MAX_STEPS,
    ConformanceResult,
    Run,
    run,
    sweep,
    unavailable,
)
from tumble.conformance.scenarios import SCENARIOS, Scenario, get_scenario, scenario_names

__all__ = [
    "ENGINES",
    "EXTRA",
    "MAX_STEPS",
    "SCENARIOS",
    "ConformanceResult",
    "Engine",
    "EngineBody",
    "Run",
    "Samples",
    "Scenario",
    "engine_names",
    "get_scenario",
    "register_engine",
    "run",
    "scenario_names",
    "sweep",
    "unavailable",
]

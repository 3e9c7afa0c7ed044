"""What configuration files may name, read from tumble's registries when a file is read.

Scenario and sweep files name integrators (``method``), torque models
(``[[torques]] type``) and theory checks (``[theory] model``); the allowed
values are never listed here: they come from
:data:`tumble.integrators.INTEGRATORS`, :data:`tumble.torques.TORQUES` and
:data:`tumble.checks.THEORY_CHECKS` at validation time, so a model, method
or check registered later (a user's, a test's) is accepted by both file
formats without a change to either schema.
"""

from __future__ import annotations

from typing import Any

from tumble.config.errors import key_error, unknown_key
from tumble.errors import InputError, unknown_choice

__all__ = [
    "actuator_choice",
    "method_choice",
    "part_entry",
    "theory_choice",
    "torque_entry",
    "torque_types",
]


def method_choice(value: Any, *, batch: bool = False) -> str:
    """``value`` if it names a registered integrator (with batch kernels measured
    as they step, for ``batch``: sweeps; else also ``"auto"``).

    Raises
    ------
    InputError
        Another value (:func:`tumble.integrators.check_method`).
    """
    from tumble.integrators import check_method

    return check_method(value, measured=batch)


def theory_choice(value: Any) -> str:
    """``value`` if it is ``"auto"``, ``"none"`` or the name of a registered theory
    check (:data:`tumble.checks.THEORY_CHECKS`).

    Raises
    ------
    InputError
        Another value; the message lists the choices.
    """
    from tumble.checks import THEORY_CHECKS

    names = ["auto", "none", *THEORY_CHECKS]
    if value not in names:
        raise unknown_choice(value, names, "`model`")
    return str(value)


def actuator_choice(value: Any) -> str:
    """``value`` if it names where a torque comes from (:data:`tumble.torques.ACTUATORS`).

    Raises
    ------
    pydantic error at ``actuator``
        Another value; the message lists the choices.
    """
    from tumble.torques import ACTUATORS

    if value not in ACTUATORS:
        raise key_error("actuator", str(unknown_choice(value, ACTUATORS, "`actuator`")))
    return str(value)


def torque_types() -> list[str]:
    """The ``type`` names of the torque models files may use."""
    from tumble.torques import TORQUES

    return [name for name, model in TORQUES.items() if model.in_files]


def torque_entry(data: Any) -> Any:
    """Check one ``[[torques]]`` table against the torque registry: its ``type`` is a
    model files may use, its other keys are exactly that model's parameters,
    each converted to SI (:meth:`tumble.torques.Parameter.convert`).

    Returns ``{"type": name, "values": {parameter: value}}`` (data that is not a
    table is returned as it is, for pydantic to refuse); raises pydantic errors
    located at the key at fault.
    """
    from tumble.torques import TORQUES

    if not isinstance(data, dict):
        return data
    names = torque_types()
    kind = data.get("type")
    if kind is None:
        raise key_error("type", f"Expected `type` ({', '.join(names)}), which is missing.")
    if kind not in names:
        raise key_error("type", str(unknown_choice(kind, names, "`type`")))
    model = TORQUES[kind]
    known = ["type", *(parameter.name for parameter in model.parameters)]
    if model.drives_rotors:
        known.append("actuator")
    for key in data:
        if key not in known:
            raise unknown_key(str(key), known)
    values: dict[str, Any] = {}
    if "actuator" in data:
        values["actuator"] = actuator_choice(data["actuator"])
    for parameter in model.parameters:
        if parameter.name not in data and parameter.optional:
            continue
        if parameter.name not in data:
            raise key_error(
                parameter.name,
                f"Expected `{parameter.name}` ({parameter.description}) for a {kind} torque, "
                "which is missing.",
            )
        try:
            values[parameter.name] = parameter.convert(data[parameter.name], per_body=False)
        except InputError as exc:
            raise key_error(parameter.name, str(exc)) from None
    return {"type": kind, "values": values}


def part_entry(data: Any) -> Any:
    """Check one ``[[internal]]`` table against the part registry
    (:data:`tumble.parts.PARTS`): its ``type`` is a registered kind, its other
    keys are that kind's keys in files
    (:meth:`tumble.parts.InternalPart.keys_in_files`), each converted to SI.

    Returns ``{"type": kind, "values": {key: value}}`` (data that is not a table
    is returned as it is, for pydantic to refuse); raises pydantic errors
    located at the key at fault. The part is made once
    (:meth:`tumble.parts.InternalPart.from_table`), so that the values are
    checked together (a key that is missing, a value the part refuses).
    """
    from tumble.parts import PARTS, TableKeyError, part_class

    if not isinstance(data, dict):
        return data
    kind = data.get("type")
    if kind is None:
        raise key_error("type", f"Expected `type` ({', '.join(PARTS)}), which is missing.")
    try:
        cls = part_class(kind)
    except InputError as exc:
        raise key_error("type", str(exc)) from None
    keys = {parameter.name: parameter for parameter in cls.keys_in_files()}
    elsewhere = {p.name for other in PARTS.values() for p in other.keys_in_files()}
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key == "type":
            continue
        if key not in keys:
            if key in elsewhere:
                raise key_error(str(key), f"Expected no `{key}` for a {kind}, got one.")
            raise unknown_key(str(key), ["type", *keys])
        try:
            values[key] = keys[key].convert(value, per_body=False)
        except InputError as exc:
            raise key_error(str(key), str(exc)) from None
    try:
        cls.from_table(values)
    except TableKeyError as exc:
        raise key_error(exc.key, str(exc)) from None
    except InputError as exc:
        raise ValueError(str(exc)) from None
    return {"type": kind, "values": values}

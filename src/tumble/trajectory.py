"""A simulated rotation: :class:`Trajectory`, its physical quantities, its Parquet files.

The angular momentum, the energy and the conserved quantities of a trajectory
come from its body model (:class:`tumble.body.RigidBody`, with the parts it
carries) and its torque models (:mod:`tumble.torques`): each model that declares
a potential energy (gravity about a pivot, a user torque with a potential) adds
it to the energy. Its drift report lists exactly the quantities its motion
conserves (:data:`tumble.invariants.INVARIANTS`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from tumble._version import __version__
from tumble.body import RigidBody, body_model
from tumble.errors import InputError, unknown_choice
from tumble.files import replaced
from tumble.invariants import INVARIANTS, label
from tumble.massprops import MassProperties
from tumble.parts import InternalPart, from_description, spin_columns, value_columns
from tumble.torques import TorqueModel
from tumble.torques import from_description as torque_from_description

__all__ = ["Trajectory"]

Array = NDArray[np.float64]


def _lengths(vectors: Array) -> Array:
    """(n,) the lengths of (n, 3) vectors, by hypot: no overflow or underflow
    of their squares (L of a body of 1e200 kg·m², or 1e-200)."""
    return np.asarray(np.hypot.reduce(vectors, axis=1))


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A simulated rotation, sampled at times ``t``.

    Attributes
    ----------
    t : (n,) s.
    omega : (n, 3) angular velocity in body coordinates, rad/s.
    quaternion : (n, 4) unit quaternions ``[w, x, y, z]``, body → space.
    mass_properties : the body.
    pivot : None (free body) or the fixed body point, m.
    method : the integrator that ran; ``reason``: why it was chosen.
    dt : the integration step used (fixed-step methods) or the sampling
        interval (exact, adaptive), s.
    steps : integration steps taken (accepted steps for the adaptive method;
        0 for the exact solution).
    conserved : the quantities the motion conserves (keys of
        :data:`tumble.invariants.INVARIANTS`), as :func:`tumble.simulate` found them
        from the body and its torques; None: those of the body under the
        models of ``torque`` that act on it.
    invariant_values : quantities a model computed itself, by name (n,) (e.g.
        the gyrocompass's ``jacobi_integral``); they count as conserved.
    internal : the parts the body carries (:mod:`tumble.parts`), in order; the
        mass properties hold them as if locked.
    internal_values : (n, k) their values over time, in the order of ``internal``:
        a rotor's spin rate relative to the body (rad/s), a damper sphere's
        angular velocity (rad/s, body axes, three columns).
    torque : the torque models the body was under (:mod:`tumble.torques`), gravity
        included, or None: their potentials enter :attr:`energy`, their uniform
        gravity is :attr:`gravity`.
    potential : None, or (n,) the potential energy at each sample, J, as recorded
        (a trajectory file's ``potential_energy`` column, which holds the
        potential of a user's function too); None: computed from ``torque``.

    Examples
    --------
    A brick spun about its axis of least moment, for one second, sampled
    every 0.1 s:

    >>> import numpy as np
    >>> import tumble as tb
    >>> brick = tb.shapes.box(1.0, [0.1, 0.2, 0.3])
    >>> traj = tb.simulate(brick, [0.0, 0.1, 5.0], duration=1.0, dt=0.1)
    >>> traj.t.shape, traj.omega.shape, traj.quaternion.shape
    ((11,), (11, 3), (11, 4))
    >>> traj.conserved_quantities
    ('energy', 'angular_momentum_vector')
    >>> print(f"E = {traj.energy[0]:.6f} J")  # ½ ω·(I ω)
    E = 0.052125 J
    >>> all(drift < 1e-12 for drift in traj.drift.values())
    True
    >>> traj.samples(slice(None, None, 5)).t.tolist()
    [0.0, 0.5, 1.0]
    """

    t: Array
    omega: Array
    quaternion: Array
    mass_properties: MassProperties
    pivot: Array | None
    method: str
    reason: str
    dt: float
    steps: int = 0
    conserved: tuple[str, ...] | None = None
    invariant_values: Mapping[str, Array] = field(default_factory=dict)
    internal: tuple[InternalPart, ...] = ()
    internal_values: Array | None = None
    torque: TorqueModel | None = None
    potential: Array | None = None

    def __post_init__(self) -> None:
        if self.internal_values is None:
            object.__setattr__(self, "internal_values", np.zeros((len(self.t), 0)))

    @classmethod
    def of_fields(cls, **fields: Any) -> Trajectory:
        """A trajectory given every one of its fields by name, as they are (no
        defaults, no ``__post_init__``): what :func:`tumble.simulate` returns.

        The generated ``__init__`` sets the fields one by one through
        ``object.__setattr__``; made so, a short run repeated takes 8 µs less when
        the processor's caches are cold (of 0.09 ms: ``bench/cold_call.py``).

        Raises
        ------
        InputError
            Fields missing, or names that are none of its fields.
        """
        if fields.keys() != _FIELD_NAMES:
            missing = sorted(_FIELD_NAMES - fields.keys())
            unknown = sorted(fields.keys() - _FIELD_NAMES)
            raise InputError(
                f"Expected every field of a Trajectory, got {len(missing)} missing "
                f"({', '.join(missing) or 'none'}) and {len(unknown)} unknown "
                f"({', '.join(unknown) or 'none'})."
            )
        trajectory = object.__new__(cls)
        vars(trajectory).update(fields)
        return trajectory

    def samples(self, index: Any) -> Trajectory:
        """The trajectory at some of its samples (an index or slice into ``t``)."""
        return dataclasses.replace(
            self,
            t=self.t[index],
            omega=self.omega[index],
            quaternion=self.quaternion[index],
            invariant_values={k: np.asarray(v)[index] for k, v in self.invariant_values.items()},
            internal_values=self._part_values[index],
            potential=None if self.potential is None else np.asarray(self.potential)[index],
        )

    @property
    def _part_values(self) -> Array:
        """(n, k) :attr:`internal_values` (an empty (n, 0) without parts)."""
        return cast(Array, self.internal_values)

    @cached_property
    def body(self) -> RigidBody:
        """The body model: the body turning about its centre of mass or the pivot,
        with its parts."""
        return body_model(self.mass_properties, self.pivot, self.internal)

    @cached_property
    def rotor_speed(self) -> Array:
        """(n, k) the spin rates of the rotors relative to the body, rad/s, in the
        order given (``(n, 0)`` without rotors): the values of the parts that spin
        (:attr:`tumble.parts.InternalPart.spin`)."""
        return np.asarray(self._part_values[:, list(spin_columns(self.internal))])

    @cached_property
    def rotation(self) -> Any:
        """The attitudes as one scipy ``Rotation`` (n rotations), body → space."""
        return Rotation.from_quat(self.quaternion, scalar_first=True)

    @cached_property
    def _matrices(self) -> Array:
        return np.asarray(self.rotation.as_matrix())

    @cached_property
    def omega_space(self) -> Array:
        """(n, 3) angular velocity in space coordinates, rad/s."""
        return np.einsum("nij,nj->ni", self._matrices, self.omega)

    @cached_property
    def angular_momentum(self) -> Array:
        """(n, 3) angular momentum in space coordinates, kg·m²/s, about the centre
        of mass (free body) or about the pivot; the parts' included."""
        return np.einsum("nij,nj->ni", self._matrices, self.body_momentum)

    @cached_property
    def body_momentum(self) -> Array:
        """(n, 3) the same angular momentum in body coordinates, kg·m²/s."""
        return self.body.angular_momentum(self.omega, self._part_values)

    @cached_property
    def gravity(self) -> Array:
        """(3,) the uniform gravitational acceleration the body was under, m/s², space
        axes: the sum of what the models of ``torque`` declare
        (:meth:`tumble.torques.TorqueModel.uniform_gravity`); zeros without."""
        found = None if self.torque is None else self.torque.uniform_gravity()
        return np.zeros(3) if found is None else np.asarray(found, dtype=float)

    @cached_property
    def potential_energy(self) -> Array:
        """(n,) potential energy, J: the sum of the potentials U(t, q) of the torque
        models that declare one (:meth:`tumble.torques.TorqueModel.potential_energy`:
        gravity about the pivot, −m g · r; a user torque's ``potential``), or as
        recorded in the file read; zeros when none does."""
        if self.potential is not None:
            return np.asarray(self.potential, dtype=float)
        found = self._potential_of_models()
        return np.zeros(len(self.t)) if found is None else found

    def _potential_of_models(self) -> Array | None:
        """The potential of the torque models at the samples, J, or None when none
        declares one."""
        if self.torque is None:
            return None
        found = self.torque.potential_energy(self.body, self.t, self.quaternion)
        return None if found is None else np.asarray(found, dtype=float)

    @cached_property
    def energy(self) -> Array:
        """(n,) total energy, J: rotational kinetic energy (about the centre of mass,
        or about the pivot; the parts' included), plus the potential energy of the
        torque models (:attr:`potential_energy`)."""
        kinetic = self.body.kinetic_energy(self.omega, self._part_values)
        return np.asarray(kinetic + self.potential_energy)

    # ------------------------------------------------------------ invariants
    @cached_property
    def conserved_quantities(self) -> tuple[str, ...]:
        """The names of the quantities this motion conserves, in the order of
        :data:`tumble.invariants.INVARIANTS`."""
        names = self.conserved
        if names is None:
            terms = () if self.torque is None else self.torque.terms
            names = self.body.conserved([term for term in terms if term.acts_on(self.body)])
        return tuple(dict.fromkeys((*names, *self.invariant_values)))

    def invariant(self, name: str) -> Array:
        """The values over time of a quantity of :data:`tumble.invariants.INVARIANTS`:
        (n,), or (n, 3) for the vector L (space axes)."""
        if name in self.invariant_values:
            return np.asarray(self.invariant_values[name], dtype=float)
        momentum = self.angular_momentum
        if name == "energy":
            return self.energy
        if name == "angular_momentum_vector":
            return momentum
        if name == "angular_momentum_norm":
            return _lengths(momentum)
        if name == "angular_momentum_vertical":
            size = math.hypot(*self.gravity)
            if size == 0.0:
                raise InputError("Expected gravity for `angular_momentum_vertical`, got none.")
            return np.asarray(momentum @ (-self.gravity / size))
        if name == "angular_momentum_axial":
            lever = self.body.lever
            axis = lever / max(math.hypot(*lever), np.finfo(float).tiny)
            return np.asarray(self.body_momentum @ axis)
        raise unknown_choice(name, INVARIANTS, "a quantity", alternative="a model's own quantity")

    def relative_change(self, name: str) -> Array:
        """(n,) the change of a conserved quantity from its initial value, relative:
        energies to their largest magnitude, components of L and the vector L (the
        length of its change) to the largest |L| of the run (with parts, to the
        largest momentum the body or a part carries, when that is larger). A body
        released from rest under gravity starts with |L| at round-off: its
        conserved vertical component is measured against the momentum it swings
        with, not against that."""
        values = self.invariant(name)
        if name.startswith("angular_momentum"):
            scale = max(float(np.max(_lengths(self.angular_momentum))), self._momentum_scale)
        else:
            scale = float(np.max(np.abs(values)))
        # Scaled by a power of two (exact) to order one before the change and its
        # length: the squares of L at 1e200 kg·m²/s overflow, those of a change
        # at 1e-200 underflow, and the change of values near the largest float
        # could overflow.
        exponent = math.frexp(scale)[1] if math.isfinite(scale) else 0
        scaled = np.ldexp(values, -exponent)
        change = scaled - scaled[0]
        if change.ndim == 2:
            change = _lengths(change)
        return np.asarray(change / max(math.ldexp(scale, -exponent), np.finfo(float).tiny))

    @cached_property
    def _momentum_scale(self) -> float:
        """With parts, the largest angular momentum the body or one of its parts
        carries over the run (kg·m²/s): the scale of L's drift when the total is
        small (a rest-to-rest slew by reaction wheels keeps L = 0); 0 without."""
        if not self.internal:
            return 0.0
        body = self.body
        sizes = [_lengths(self.omega @ body.platform_inertia.T)]
        for part, values in zip(self.internal, body.split_values(self._part_values), strict=True):
            sizes.append(_lengths(part.momentum(self.omega, values)))
        return float(np.max(sizes))

    @cached_property
    def drift(self) -> dict[str, float]:
        """Largest relative change (:meth:`relative_change`) over the trajectory of
        each quantity the motion conserves, and of nothing else."""
        return {
            name: float(np.max(np.abs(self.relative_change(name))))
            for name in self.conserved_quantities
        }

    def __repr__(self) -> str:
        kind = "free body" if self.pivot is None else f"pivot at {self.pivot.tolist()} m"
        if self.internal:
            kind += f", {len(self.internal)} internal part{'s' if len(self.internal) > 1 else ''}"
        drift = ", ".join(f"{label(name)} {value:.2e}" for name, value in self.drift.items())
        return (
            f"Trajectory({len(self.t)} samples over {self.t[-1]:.6g} s, {kind}, "
            f"method {self.method} (dt = {self.dt:.3g} s, {self.steps} steps; {self.reason}); "
            f"relative drift: {drift or 'nothing conserved'})"
        )

    # ------------------------------------------------------------- Parquet
    def to_parquet(self, path: str | os.PathLike[str]) -> None:
        """Write the samples and the run's description to a Parquet file.

        Columns ``t, omega_x, omega_y, omega_z, q_w, q_x, q_y, q_z`` (SI, body
        axes, scalar-first body → space), the parts' values, ``potential_energy``
        (J) when a torque model declares a potential, and one column per quantity
        a model computed itself; the body, pivot, torque models (``torques``: each
        one's ``type`` and SI values; a user torque by its functions' names),
        their total uniform gravity, method, step and conserved quantities go in
        the file's metadata. Written to a temporary name and renamed, so the file
        is never half-written.

        Examples
        --------
        >>> import os
        >>> import tempfile
        >>> import numpy as np
        >>> import tumble as tb
        >>> traj = tb.simulate(tb.shapes.box(1.0, [0.1, 0.2, 0.3]), [0, 0.1, 5.0], duration=1.0)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = os.path.join(folder, "run.parquet")
        ...     traj.to_parquet(path)
        ...     back = tb.Trajectory.read_parquet(path)
        >>> np.array_equal(back.omega, traj.omega), back.method
        (True, 'exact')
        """
        import pyarrow as pa
        import pyarrow.parquet as pq

        columns = {"t": self.t}
        for k, axis in enumerate("xyz"):
            columns[f"omega_{axis}"] = self.omega[:, k]
        for k, part in enumerate("wxyz"):
            columns[f"q_{part}"] = self.quaternion[:, k]
        for name, values in zip(value_columns(self.internal), self._part_values.T, strict=True):
            columns[name] = values
        potential = self.potential
        if potential is None:
            potential = self._potential_of_models()
        if potential is not None:
            columns["potential_energy"] = np.asarray(potential, dtype=float)
        for name, values in self.invariant_values.items():
            columns[f"invariant_{name}"] = np.asarray(values, dtype=float)
        mp = self.mass_properties
        meta = {
            "tumble_version": __version__,
            "mass": mp.mass,
            "center_of_mass": mp.center_of_mass.tolist(),
            "inertia": mp.inertia.tolist(),
            "pivot": None if self.pivot is None else self.pivot.tolist(),
            "torques": [] if self.torque is None else [t.describe() for t in self.torque.terms],
            # The total of the models' uniform gravity: what files before
            # `torques` held, kept for their readers.
            "gravity": self.gravity.tolist(),
            "method": self.method,
            "reason": self.reason,
            "dt": self.dt,
            "steps": self.steps,
            "conserved": list(self.conserved_quantities),
            "internal": [part.describe() for part in self.internal],
            "units": "SI: s, rad/s, kg, m, kg*m^2; quaternion [w, x, y, z] body -> space",
        }
        table = pa.table(columns).replace_schema_metadata({"tumble": json.dumps(meta)})
        with replaced(path) as temporary:
            pq.write_table(table, temporary)

    @classmethod
    def read_parquet(cls, path: str | os.PathLike[str]) -> Trajectory:
        """Read a file written by :meth:`to_parquet`.

        The torque models that files may name come back as models; a user's
        function cannot be stored, so a :class:`tumble.torques.UserTorque` does
        not, but its potential energy does (the ``potential_energy`` column),
        and so do the energy and the drift."""
        import pyarrow.parquet as pq

        try:
            table = pq.read_table(path)
        except (OSError, ValueError) as exc:
            raise InputError(
                f"Expected a Parquet file written by tumble, got {str(path)!r}: {exc}"
            ) from None
        raw = (table.schema.metadata or {}).get(b"tumble")
        if raw is None:
            raise InputError(
                f"Expected a Parquet file written by tumble, got {str(path)!r} "
                "(no tumble metadata)."
            )
        meta = json.loads(raw)
        data = {name: table.column(name).to_numpy() for name in table.column_names}
        own = {
            name.removeprefix("invariant_"): values
            for name, values in data.items()
            if name.startswith("invariant_")
        }
        conserved = meta.get("conserved")
        internal = tuple(from_description(entry) for entry in meta.get("internal", []))
        names = value_columns(internal)
        # Files written before `torques` name only their gravity.
        described = meta.get("torques")
        if described is None:
            described = [{"type": "gravity", "acceleration": meta["gravity"]}]
        models = [m for m in map(torque_from_description, described) if m is not None]
        potential = data.get("potential_energy")
        return cls(
            t=data["t"],
            omega=np.column_stack([data[f"omega_{a}"] for a in "xyz"]),
            quaternion=np.column_stack([data[f"q_{p}"] for p in "wxyz"]),
            mass_properties=MassProperties(meta["mass"], meta["center_of_mass"], meta["inertia"]),
            pivot=None if meta["pivot"] is None else np.asarray(meta["pivot"], dtype=float),
            method=meta["method"],
            reason=meta["reason"],
            dt=float(meta["dt"]),
            steps=int(meta.get("steps", 0)),
            conserved=None if conserved is None else tuple(n for n in conserved if n not in own),
            invariant_values=own,
            internal=internal,
            internal_values=np.column_stack([data[name] for name in names]) if names else None,
            torque=sum(models[1:], models[0]) if models else None,
            potential=None if potential is None else np.asarray(potential, dtype=float),
        )

    # ------------------------------------------------------------ notebooks
    def _repr_html_(self) -> str:
        from tumble.report.html import trajectory_html

        return trajectory_html(self)

    def plot(self) -> dict[str, Any]:
        """Matplotlib figures by name: ``omega`` (ω(t), body axes), ``angular_momentum``
        (L(t), space axes), ``drift`` (the conserved quantities) and ``polhode`` (L
        in principal axes on the energy ellipsoid). See :mod:`tumble.report.plots`."""
        from tumble.report import figures

        return figures(self)

    def view(self, frames: int = 300) -> Any:
        """The interactive 3D viewer (the body as an ellipsoid of equal inertia, its
        principal axes, ω and L, play / pause and a time slider): shown inline in a
        notebook, ``.save(path)`` writes a self-contained HTML file."""
        from tumble.report import view

        return view(self, frames=frames)


#: The names of a trajectory's fields (:meth:`Trajectory.of_fields`).
_FIELD_NAMES = frozenset(f.name for f in dataclasses.fields(Trajectory))

"""The body model: what a simulation integrates, and what its motion conserves.

A :class:`RigidBody` is a body's mass properties turning about a reference
point: its centre of mass (a free body) or a pivot, a body point held fixed in
space, with the parts it carries inside (:mod:`tumble.parts`: rotors,
dampers; held in the mass properties as if locked). Everything the
integrators and the trajectories need of the body is computed here, once,
one concern a module:

* :mod:`tumble.body.model`: the model itself, the inertia about the reference
  point, the *platform inertia* that turns at the body's own rate (the inertia
  less the parts' spin inertia; the whole inertia for a body without parts) and
  its principal frame (the kernels work in it);
* :mod:`tumble.body.frames`: the changes of axes between the user's body axes
  and that frame, vectors and attitudes (:func:`compose`);
* :mod:`tumble.body.state`: the parts' state and its mapping to and from the
  kernels' state;
* :mod:`tumble.body.physics`: the angular momentum, the kinetic energy and the
  quantities its motion conserves (:data:`tumble.invariants.INVARIANTS`);
* :mod:`tumble.body.symmetry`: the symmetries that give a motion in closed form
  (a gyrostat, a symmetric gyrostat, a Lagrange top);
* :mod:`tumble.body.rates`: the fastest rates a time step must resolve;
* :mod:`tumble.body.shared`: one model per body, shared by the calls that ask
  for it (:func:`body_model`);
* :mod:`tumble.body.batch`: :class:`BodyBatch`, the same for N free bodies at
  once (:func:`tumble.simulate_batch`).

The mixins' methods take ``self`` as :class:`tumble.body.protocol.BodyModel`,
what they read of the model.

Conventions as in the rest of tumble: SI units, angular velocity in body axes,
quaternions ``[w, x, y, z]`` turning body coordinates into space coordinates.
"""

from tumble.body.batch import BodyBatch
from tumble.body.frames import compose
from tumble.body.model import ZERO_MOMENT, RigidBody
from tumble.body.shared import BODY_CACHE_SIZE, body_model

__all__ = ["BODY_CACHE_SIZE", "ZERO_MOMENT", "BodyBatch", "RigidBody", "body_model", "compose"]

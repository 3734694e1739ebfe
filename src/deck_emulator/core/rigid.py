"""Quaternions and rigid-body quantities of the post's state, in its principal axes.

State of the post (13 numbers), all in the units of the scene (ft, slug, s, rad):

* ``x, y, z``      -- mass-centre position in the road axes XX, YY, ZZ;
* ``v1, v2, v3``   -- mass-centre velocity along the body axes 1, 2, 3 (eq. 3.16's V);
* ``qw, qx, qy, qz`` -- unit quaternion turning body axes into road axes (the attitude;
  renormalised wherever it is used, so its norm never matters);
* ``w1, w2, w3``   -- angular velocity along the body axes (eq. 3.17's omega).

No Euler angles anywhere: nothing is singular at theta = 0 or cos psi = 0.

The rotation and the equations of motion are the compiled laws of :mod:`.laws`; the
helpers here work on plain Python floats.
"""

from __future__ import annotations

import math

import numpy as np

from . import laws as _laws

__all__ = [
    "N_POST",
    "rotation_matrix",
    "quat_multiply",
    "quat_normalised",
    "quat_about_axis",
    "kinetic_energy",
    "angular_momentum_world",
    "attitude_angle_between",
]

N_POST = 13


def quat_normalised(q):
    w, x, y, z = q
    n = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
    return (w * n, x * n, y * n, z * n)


def quat_multiply(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def quat_about_axis(axis, angle_rad):
    """Unit quaternion of a turn by ``angle_rad`` about the unit vector ``axis``."""
    s = math.sin(angle_rad / 2)
    return (math.cos(angle_rad / 2), axis[0] * s, axis[1] * s, axis[2] * s)


def rotation_matrix(q):
    """Row-major 3x3 (a flat 9-tuple) of the normalised quaternion ``q``: body -> road
    (eq. 3.21; the compiled law :func:`~.laws.rotation_matrix`)."""
    w, x, y, z = q
    return _laws.rotation_matrix(float(w), float(x), float(y), float(z))


def kinetic_energy(y, mass, inertia):
    """Translational plus rotational kinetic energy (ft lb) of post state(s) ``y`` (13, ...)."""
    y = np.asarray(y, dtype=float)
    v = y[3:6]
    w = y[10:13]
    inertia = np.asarray(inertia, dtype=float).reshape((3,) + (1,) * (y.ndim - 1))
    return 0.5 * mass * np.sum(v * v, axis=0) + 0.5 * np.sum(inertia * w * w, axis=0)


def angular_momentum_world(y, inertia):
    """Angular momentum about the mass centre in road components (slug ft^2/s)."""
    y = np.asarray(y, dtype=float)
    if y.ndim == 1:
        R = np.array(rotation_matrix(y[6:10])).reshape(3, 3)
        return R @ (np.asarray(inertia) * y[10:13])
    return np.stack([angular_momentum_world(col, inertia) for col in y.T], axis=-1)


def attitude_angle_between(q1, q2):
    """Angle (rad) of the rotation taking attitude ``q1`` to ``q2`` (sign of q ignored)."""
    aw, ax, ay, az = quat_normalised(q1)
    rw, rx, ry, rz = quat_multiply((aw, -ax, -ay, -az), quat_normalised(q2))
    return 2.0 * math.atan2(math.sqrt(rx * rx + ry * ry + rz * rz), abs(rw))

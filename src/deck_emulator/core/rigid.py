"""Rigid-body kinematics and the Newton-Euler equations in the post's principal axes.

State of the post (13 numbers), all in the units of the scene (ft, slug, s, rad):

* ``x, y, z``      -- mass-centre position in the road axes XX, YY, ZZ;
* ``v1, v2, v3``   -- mass-centre velocity along the body axes 1, 2, 3 (eq. 3.16's V);
* ``qw, qx, qy, qz`` -- unit quaternion turning body axes into road axes (the attitude;
  renormalised wherever it is used, so its norm never matters);
* ``w1, w2, w3``   -- angular velocity along the body axes (eq. 3.17's omega).

No Euler angles anywhere: nothing is singular at theta = 0 or cos psi = 0.

The functions here use plain Python floats: for 3-vectors that is several times faster
than NumPy, and the right-hand side is called tens of thousands of times per run.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "N_POST",
    "rotation_matrix",
    "quat_multiply",
    "quat_normalised",
    "quat_about_axis",
    "rotate",
    "rotate_back",
    "post_derivative",
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
    """Row-major 3x3 (a flat 9-tuple) of the normalised quaternion ``q``: body -> road.

    It is eq. 3.21 with ``(w, x, y, z) = (chi, xi, eta, zeta)``.
    """
    w, x, y, z = quat_normalised(q)
    return (
        w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z,
    )  # fmt: skip


def rotate(R, v):
    """``R @ v`` for a flat row-major ``R``."""
    return (
        R[0] * v[0] + R[1] * v[1] + R[2] * v[2],
        R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
        R[6] * v[0] + R[7] * v[1] + R[8] * v[2],
    )


def rotate_back(R, v):
    """``R.T @ v``: road components -> body components (eq. 3.29, 3.31)."""
    return (
        R[0] * v[0] + R[3] * v[1] + R[6] * v[2],
        R[1] * v[0] + R[4] * v[1] + R[7] * v[2],
        R[2] * v[0] + R[5] * v[1] + R[8] * v[2],
    )


def post_derivative(y, R, force_road, torque_road, mass, inertia):
    """Time derivative of the 13 post states (eq. 3.16, 3.17 and the kinematics).

    ``force_road``: total force, ``torque_road``: total torque about the mass centre,
    both in road components.  Returns a list of 13 floats.
    """
    v1, v2, v3 = y[3], y[4], y[5]
    qw, qx, qy, qz = y[6], y[7], y[8], y[9]
    w1, w2, w3 = y[10], y[11], y[12]
    a, b, c = inertia
    f1, f2, f3 = rotate_back(R, force_road)
    t1, t2, t3 = rotate_back(R, torque_road)
    vx, vy, vz = rotate(R, (v1, v2, v3))
    return [
        vx,
        vy,
        vz,
        # eq. 3.16: M (V' + omega x V) = F
        f1 / mass - (w2 * v3 - w3 * v2),
        f2 / mass - (w3 * v1 - w1 * v3),
        f3 / mass - (w1 * v2 - w2 * v1),
        # q' = q (x) (0, omega) / 2
        0.5 * (-qx * w1 - qy * w2 - qz * w3),
        0.5 * (qw * w1 + qy * w3 - qz * w2),
        0.5 * (qw * w2 - qx * w3 + qz * w1),
        0.5 * (qw * w3 + qx * w2 - qy * w1),
        # eq. 3.17: A w1' - (B - C) w2 w3 = T1 ...
        ((b - c) * w2 * w3 + t1) / a,
        ((c - a) * w3 * w1 + t2) / b,
        ((a - b) * w1 * w2 + t3) / c,
    ]


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

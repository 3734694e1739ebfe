"""State layout, the contact mode, event specifications and point kinematics."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from . import laws as _laws
from .rigid import N_POST, rotation_matrix

__all__ = ["IDX_SV", "IDX_VV", "N_STATE", "ContactMode", "EventSpec", "Kinematics",
           "state_vector"]

IDX_SV = N_POST  # vehicle position along XV (ft)
IDX_VV = N_POST + 1  # vehicle velocity along XV (ft/s)
N_STATE = N_POST + 2


def state_vector(post, car_position_ft: float = 0.0, car_velocity_ft_s: float = 0.0):
    """The core's state (:data:`N_STATE` numbers) of a post's motion ``post`` (a
    :class:`~deck_emulator.vocabulary.scene.PostInitialState` whose attitude turns body axes into
    road axes, the principal tilt included) and the car's position and velocity along XV."""
    return [*post.mass_centre_ft, *post.velocity_body_ft_s, *post.attitude_wxyz,
            *post.angular_velocity_body_rad_s, car_position_ft, car_velocity_ft_s]


@dataclass(frozen=True)
class ContactMode:
    """The discrete state of the contact phase; changed only by located events.

    ``contact_point``: where the spring force acts ("S" or "T").  ``window``: the
    start-up kick's windows ("kick", "first_step") or ``None``.

    Sliding modes (Filippov; :mod:`.sliding`): ``cap_sliding`` -- the ``FCONST`` cap's
    switching surface is held (the spring force is the one that keeps ``DIFF``
    stationary, between the cap and the uncapped force); ``friction_stick`` -- the base
    sticks (the friction is the reaction that holds it, bounded by its limit);
    ``friction_sign`` -- the sign of the base's sliding velocity along ``XX`` while it
    slips (the friction acts against it).
    """

    contact_point: str = "S"
    first_spring_lost: bool = False
    normal_on: bool = False
    friction_on: bool = False
    cap_armed: bool = False
    cap_engaged: bool = False
    window: str | None = None
    #: a leaf spring's largest compression so far while it unloads (ft); None: loading
    spring_peak_ft: float | None = None
    cap_sliding: bool = False
    friction_stick: bool = False
    friction_sign: float = 0.0


class EventSpec:
    """One event function for ``solve_ivp`` (callable with ``terminal``/``direction``):
    ``code``, the function among the compiled laws' events, ``(EV_* code, argument)``
    (:func:`~.laws.contact_event`, :func:`~.dop853._event`); ``function``, what ``solve_ivp``
    calls (a contact event's is :func:`~.laws.contact_event` itself,
    :func:`~.sliding.contact_events`)."""

    __slots__ = ("name", "function", "direction", "terminal", "code")

    def __init__(self, name: str, direction: float, code: tuple[int, float], *,
                 terminal: bool = True, function: Callable | None = None):
        self.name = name
        self.function = function
        self.direction = direction
        self.terminal = terminal
        self.code = code

    def __call__(self, t, y):
        return self.function(t, y)

    def __repr__(self) -> str:
        return f"EventSpec({self.name!r}, direction={self.direction}, terminal={self.terminal})"


class Kinematics:
    """Positions and velocities of the post's points at one state, computed on demand."""

    __slots__ = ("model", "y", "R", "_pos")

    def __init__(self, model, y):
        if not isinstance(y, list):
            y = y.tolist()
        self.model = model
        self.y = y
        self.R = rotation_matrix((y[6], y[7], y[8], y[9]))
        self._pos: dict[str, tuple] = {}

    def point(self, letter: str):
        """Point position, road axes XX, YY, ZZ (ft)."""
        p = self._pos.get(letter)
        if p is None:
            p = self.model.point_position(self, letter)
            self._pos[letter] = p
        return p

    def point_velocity(self, letter: str):
        """Point velocity, road axes (ft/s): ``R (V + omega x r_body)``."""
        y = self.y
        bx, by, bz = self.model.body_points[letter]
        return _laws.point_velocity(self.R, y[3], y[4], y[5], y[10], y[11], y[12], bx, by, bz)

"""The core's contact dynamics linearised, for what a study says about stiffness: the eigenvalues
of the contact right-hand side on a state of the contact (:func:`contact_spectrum`), and the
core's own estimate of the contact's stiffness, the one its ``method="auto"`` switches on
(:func:`stiffness_estimate`, :data:`STIFF_RATIO`).  Through here, so that the studies reach the
core's model only through the engine layer."""

from __future__ import annotations

import numpy as np

from deck_emulator.vocabulary import defaults


def stiff_ratio() -> float:
    """The core's threshold: above it ``method="auto"`` integrates the contact with Radau."""
    from deck_emulator.core.solve import STIFF_RATIO

    return STIFF_RATIO


def stiffness_estimate(scene, options) -> tuple[float, float, float]:
    """The core's own ``(ratio, fastest, slowest)`` estimate for ``scene`` under ``options``
    (:func:`deck_emulator.core.solve.stiffness`)."""
    from deck_emulator.core.model import assemble
    from deck_emulator.core.solve import stiffness

    return stiffness(assemble(scene.checked(), options))


def contact_spectrum(scene, options, *, rtol: float = defaults.STUDY_RTOL,
                     until_s: float = 1e-3) -> dict:
    """The moduli of the eigenvalues of the core's contact right-hand side (its Jacobian by
    central differences, relative step 1e-6) on a state of the contact: the scene run by the
    core (DOP853 at ``rtol``) to the car's release or ``until_s``, whichever comes first, the
    state at half that time, the spring acting at S (the contact's first mode).
    ``moduli``: largest first; ``t_s``: the state's time; ``contact_s``: the release (None
    when the contact lasts past ``until_s``)."""
    from deck_emulator.core import simulate
    from deck_emulator.core.kinematics import ContactMode
    from deck_emulator.core.model import assemble

    scene = scene.checked()
    res = simulate(scene, options, method="DOP853", rtol=rtol, atol=rtol, t_max_s=until_s,
                   check=False)
    end = res.contact_end_s if res.contact_end_s is not None else until_s
    t = 0.5 * end
    y = np.asarray(res.trajectory.state(t), dtype=float)
    fun = assemble(scene, options).contact_rhs(ContactMode())
    jac = np.empty((y.size, y.size))
    for i in range(y.size):
        dy = 1e-6 * max(1.0, abs(y[i]))
        up, down = y.copy(), y.copy()
        up[i] += dy
        down[i] -= dy
        jac[:, i] = (np.asarray(fun(t, up)) - np.asarray(fun(t, down))) / (2 * dy)
    moduli = np.sort(np.abs(np.linalg.eigvals(jac)))[::-1]
    return {"moduli": moduli, "t_s": t, "contact_s": res.contact_end_s}

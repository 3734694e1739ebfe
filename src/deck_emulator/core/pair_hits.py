"""Two luminaires landing together: the twin-luminaire post's "R&U" ground hit.

The report's Table 12 (twin post, 40 mph, 0 deg) ends "POST HITS GROUND WITH POINTS R&U".
The listing has no point U, so the rule is ours, written to match the listing's own test:
a point is on the ground when it is inside the band ``|ZZ + HEIGHT| <= 0.1`` ft, and the
listing looks at all its points once per step.  Here the run stops when the first of R
and U enters the band (a located event); the hit is "R&U" when at that instant the other
luminaire is inside the band too -- both would be seen in the band at one step of the
listing.  In a planar run (alpha = 0, a symmetric twin) R and U move as mirror images
and enter the band at the same instant, so the rule can only say "together".
"""

from __future__ import annotations

import dataclasses

from deck_emulator.vocabulary.events import JOINT_GROUND_MESSAGE, EventKind
from deck_emulator.vocabulary.defaults import LISTING_GROUND_TOLERANCE_FT
from .result import CoreEvent, CoreResult, Hit

__all__ = ["joint_ground_hit", "GROUND_BAND_FT"]

GROUND_BAND_FT = LISTING_GROUND_TOLERANCE_FT["R"]


def joint_ground_hit(result: CoreResult, band_ft: float = GROUND_BAND_FT) -> CoreResult:
    """The result with its hit renamed "POINTS R&U" when R or U hit the ground and the
    other luminaire was inside the ground band at that instant; else unchanged."""
    hit = result.hit
    if hit is None or hit.surface != "GROUND" or hit.point not in ("R", "U"):
        return result
    pts = result.terminal_points_ft  # R and U at the hit, in the report's axes
    if pts.get("R") is None or pts.get("U") is None:
        return result
    other = "U" if hit.point == "R" else "R"
    # the other point "in the band" to the event location's accuracy (1e-6 ft)
    if abs(pts[other][2]) > band_ft + 1e-6:
        return result
    msg = JOINT_GROUND_MESSAGE.format(points="R&U")
    new_hit = Hit(msg, hit.time_s, "R&U", "GROUND")
    events = tuple(
        CoreEvent(e.name, e.time_s, msg) if e.name == EventKind.HIT else e for e in result.events
    )
    return dataclasses.replace(result, hit=new_hit, events=events)

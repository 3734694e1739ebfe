#!/usr/bin/env python3
"""The core's two paths, per scene, in one run: the scipy path (``simulate``) and the
compiled batch (``simulate_batch``), process CPU time after a warm-up, medians of repeats.

    python benchmarks/bench_core_compiled.py [--repeat 5] [--scenes 100]

One steel40 scene (legacy preset), then ``--scenes`` of the sweep's scenes (steel40 with its
speed and angle changed), each preset.  The measurement is :func:`time_per_scene`; nothing
here passes or fails.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from deck_emulator.core import simulate, simulate_batch
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL, ModelOptions
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.decks import path
from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.sweep import scene_deck


def time_per_scene(scenes, options: ModelOptions, *, repeats: int = 5) -> dict:
    """Process CPU time per scene (s) of both paths on ``scenes`` after a warm-up run:
    ``{"compiled": median, "scipy": median, "ratio": scipy / compiled, "n": scenes}``,
    medians over ``repeats`` repetitions (for the benchmark)."""

    scenes = list(scenes)
    simulate_batch(scenes[:1], options)  # warm-up: load or compile the laws
    simulate(scenes[0], options)

    def per_scene(run) -> float:
        times = []
        for _ in range(repeats):
            t0 = time.process_time()
            run()
            times.append((time.process_time() - t0) / len(scenes))
        return float(np.median(times))

    compiled = per_scene(lambda: simulate_batch(scenes, options))
    scipy_s = per_scene(lambda: [simulate(s, options) for s in scenes])
    return {"compiled": compiled, "scipy": scipy_s, "ratio": scipy_s / compiled,
            "n": len(scenes)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--scenes", type=int, default=100)
    a = ap.parse_args()
    base = read_deck(path("steel40"))
    many = [Scene.from_deck(scene_deck(base, 10.0 + 50.0 * i / a.scenes, 50.0 * (i * 7 % a.scenes)
                                       / a.scenes)) for i in range(a.scenes)]
    print(f"{'scenes':>28} {'scipy ms':>9} {'compiled ms':>12} {'ratio':>6} {'compiled/s':>11}")
    for label, scenes, options in (("steel40, legacy", [Scene.from_deck(base)], LEGACY),
                                   ("steel40, physical", [Scene.from_deck(base)], PHYSICAL),
                                   (f"{a.scenes} sweep scenes, legacy", many, LEGACY),
                                   (f"{a.scenes} sweep scenes, physical", many, PHYSICAL)):
        t = time_per_scene(scenes, options, repeats=a.repeat if len(scenes) == 1 else 1)
        print(f"{label:>28} {t['scipy'] * 1e3:9.2f} {t['compiled'] * 1e3:12.2f} "
              f"{t['ratio']:6.1f} {1.0 / t['compiled']:11.0f}")


if __name__ == "__main__":
    main()

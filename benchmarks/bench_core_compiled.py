#!/usr/bin/env python3
"""The core's two paths, per scene, in one run: the scipy path (``simulate``) and the
compiled batch (``simulate_batch``), process CPU time after a warm-up, medians of repeats.

    python benchmarks/bench_core_compiled.py [--repeat 5] [--scenes 100]

One steel40 scene (legacy preset), then ``--scenes`` of the sweep's scenes (steel40 with its
speed and angle changed), each preset.  The measurement is
:func:`deck_emulator.core.batch.time_per_scene`; nothing here passes or fails.
"""

from __future__ import annotations

import argparse

from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL
from deck_emulator.core.batch import time_per_scene
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.decks import path
from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.sweep import scene_deck


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

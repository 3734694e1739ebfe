"""The option groups of the commands that run more than the listing: a SOURCE that may be a
scene, the core's preset, the cluster a many-scene command runs on, a study's folder (rows of the same kind as
:mod:`.options`, apart so that the 1967 path's commands do not make them at every start)."""

from __future__ import annotations

import os

from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.choices import PRESETS

from .options import (SOURCE_HELP, Common, Source, option, options_class, positive_int,
                      quiet_option, worker_wait)


@options_class
class SceneSource(Source):
    """SOURCE for the commands that also take a scene file."""

    source: str = option(positional=True, metavar="SOURCE", help=SOURCE_HELP)


@options_class
class Preset:
    preset: str = option(defaults.CORE_PRESET, choices=PRESETS,
                         help="core model options: legacy (the listing's quirks, the default) "
                         "or physical (none)")
    shaft_contact: bool | None = option(None, negatable=True,
                                        help="check the shaft Q-P and the arms as segments "
                                        "against the car, not only the points P, R, C "
                                        "(default: the preset's, on in physical, off in "
                                        "legacy: the listing never did it)")

    def core_keywords(self) -> dict:
        """--preset and --shaft-contact as the core engine's keywords (the engine layer's one
        rule: shaft_contact left out when not given, the preset's)."""
        from deck_emulator.engine import core_keywords

        return core_keywords(self.preset, self.shaft_contact)


@options_class
class Cluster:
    """Where a many-scene command runs."""

    jobs: int | None = option(None, parse=positive_int, metavar="N",
                              help="worker processes of the embedded runner (default: "
                              f"every core, {os.cpu_count() or 1} here)")
    scheduler: str | None = option(None, metavar="ADDRESS",
                                   help="run on an existing Dask cluster (its scheduler's "
                                   "address, tcp://host:8786) instead of the embedded runner's "
                                   "--jobs workers")
    worker_wait: float | None = option(None, parse=worker_wait, metavar="SECONDS",
                                       help="with --scheduler: how long to wait for a worker, "
                                       "at the start and whenever every worker is gone, before "
                                       f"the run ends with exit status 3 (default {defaults.WORKER_WAIT_S:g})")
    resume: bool = option(False, help="run only the scenes not yet stored in the output "
                          "directory")


@options_class
class Many(Common, Cluster):
    """What a many-scene command has: where it runs, --quiet, --json."""

    quiet: bool = quiet_option()
    json: bool = option(False, help="print what ran and what was written as one JSON object "
                        "(docs/json.md)")


@options_class
class StudyOut(Many):
    """A study's folder and size."""

    out: str = option(metavar="DIR", required=True, help="directory for the outputs")
    quick: bool = option(False, help="a small grid (seconds, for tests) instead of the full "
                         "study")

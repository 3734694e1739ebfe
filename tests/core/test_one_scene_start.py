"""A single scene's command starts what it uses: numpy's BLAS without a thread pool it never
shares work out to (OpenBLAS's documented OPENBLAS_NUM_THREADS, set by the command line before
numpy loads), unless the user set it; any other command leaves the setting as it was."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from deck_emulator import decks

SCRIPT = r"""
import os, sys
from deck_emulator import cli
code = cli.main(sys.argv[1:])
print(code, os.environ.get("OPENBLAS_NUM_THREADS"), "numpy" in sys.modules)
"""


def _threads_after(args, **env) -> list[str]:
    environ = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", SCRIPT, *args], capture_output=True,
                         text=True, check=True, env={**environ, **env})
    return out.stdout.split()[-3:]


@pytest.mark.parametrize("given, expected", [(None, "1"), ("3", "3")])
def test_core_starts_blas_with_one_thread_unless_the_user_said(given, expected):
    env = {} if given is None else {"OPENBLAS_NUM_THREADS": given}
    code, threads, numpy_loaded = _threads_after(
        ["core", str(decks.path("steel40")), "--quiet"], **env)
    assert (code, threads, numpy_loaded) == ("0", expected, "True")


def test_a_command_not_marked_one_scene_leaves_blas_as_it_was():
    code, threads, _ = _threads_after(["run", str(decks.path("steel40")), "--quiet"])
    assert (code, threads) == ("0", "None")

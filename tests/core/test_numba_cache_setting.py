"""numba's cache of the core is configured through numba's documented NUMBA_CACHE_DIR, in the
package's own processes only: a host application that imports the core keeps its numba as
it configured it."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

pytest.importorskip("numba")


def _python(code: str, **env: str) -> subprocess.CompletedProcess:
    base = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    return subprocess.run([sys.executable, "-c", code], env={**base, **env},
                          capture_output=True, text=True, check=True)


def test_importing_the_core_leaves_a_host_applications_numba_alone(tmp_path):
    host = str(tmp_path / "host-cache")
    out = _python(
        "import numba\n"
        "before = numba.config.CACHE_DIR\n"
        "import deck_emulator.core.laws, deck_emulator.core.batch\n"
        "import os\n"
        "print(before == numba.config.CACHE_DIR == os.environ['NUMBA_CACHE_DIR'])\n",
        NUMBA_CACHE_DIR=host)
    assert out.stdout.split() == ["True"]
    out = _python(
        "import numba\n"
        "before = numba.config.CACHE_DIR\n"
        "import deck_emulator.core.laws, os\n"
        "print(before == numba.config.CACHE_DIR, 'NUMBA_CACHE_DIR' in os.environ)\n")
    assert out.stdout.split() == ["True", "False"]


def test_the_package_s_own_process_points_numba_at_the_core_s_folder(tmp_path):
    out = _python(
        "from deck_emulator.core import configure_numba_cache, compiled_cache_folder\n"
        "print(configure_numba_cache())\n"
        "import numba\n"
        "print(numba.config.CACHE_DIR == compiled_cache_folder())\n",
        NUMBA_CACHE_DIR=str(tmp_path))
    assert out.stdout.split() == ["True", "True"]
    # below the user's own folder, named by the compiled modules' content
    assert _python("from deck_emulator.core import configure_numba_cache, "
                   "compiled_cache_folder\nconfigure_numba_cache()\n"
                   "import os\nprint(os.path.dirname(compiled_cache_folder()))",
                   NUMBA_CACHE_DIR=str(tmp_path)).stdout.strip() == str(tmp_path)


def test_no_setting_once_numba_is_imported():
    out = _python("import numba, os\n"
                  "from deck_emulator.core import configure_numba_cache\n"
                  "print(configure_numba_cache(), 'NUMBA_CACHE_DIR' in os.environ)\n")
    assert out.stdout.split() == ["False", "False"]

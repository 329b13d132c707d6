"""Shared fixtures of the Python front's tests (pytest, run by scripts/test.sh)."""
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def evsim_binary():
    """The evsim command-line runner built beside the module."""
    path = os.environ.get("EVSIM_BINARY") or str(REPO / "build/ws/devel/lib/endovascular_sim/evsim")
    if not os.access(path, os.X_OK):
        pytest.fail(f"no evsim binary at {path} (build with scripts/build.sh, or set EVSIM_BINARY)")
    return path


def run_evsim(binary, *args):
    """evsim's stdout (it must exit 0)."""
    done = subprocess.run([binary, *args], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout

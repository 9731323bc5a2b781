"""Shared paths and helpers of the Python tests.

The paper authors' scenes and libigl's reference results live outside the repository, in
``../shared/data`` next to the checkout (``SPLINESKIN_DATA`` overrides). Tests that need them
skip, saying so, when they are missing; with ``CI`` set, their absence is an error.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ASSETS = REPO / "crates" / "splineskin" / "assets"
DATA = Path(os.environ.get("SPLINESKIN_DATA", REPO.parent / "shared" / "data"))


def data_file(relative: str) -> Path:
    """The external data file ``relative`` (under ``../shared/data``), or a skip (an error
    with ``CI`` set) when it is missing."""
    path = DATA / relative
    if not path.exists():
        if os.environ.get("CI"):
            pytest.fail(f"{path}: missing; CI runs the tests that read the external data")
        pytest.skip(f"external data missing: {path}")
    return path


def cli() -> str:
    """The ``splineskin`` command line built in this checkout (``SPLINESKIN_BIN`` overrides)."""
    candidates = [os.environ.get("SPLINESKIN_BIN"), REPO / "target" / "debug" / "splineskin",
                  REPO / "target" / "release" / "splineskin", shutil.which("splineskin")]
    for c in candidates:
        if c and Path(c).exists():
            return str(c)
    pytest.fail("no splineskin binary: cargo build -p splineskin-cli (or set SPLINESKIN_BIN)")


def run_cli(*args: str) -> subprocess.CompletedProcess:
    """Runs the command line, failing the test with its stderr if it fails."""
    done = subprocess.run([cli(), *args], capture_output=True, text=True)
    if done.returncode != 0:
        pytest.fail(f"splineskin {' '.join(args)} failed:\n{done.stderr}")
    return done

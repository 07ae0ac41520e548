"""Shared by the tests of the Python module: where the test data and lancer's binary are."""

import os
import pathlib
import shutil

import pytest

DATA = pathlib.Path(__file__).parent / "data"
REPO = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def cbox():
    """Mitsuba's Cornell box as a pbrt-v4 scene (256x256, 64 spp, path tracer)."""
    return DATA / "cbox.pbrt"


def lancer_binary():
    """lancer's command line: $LANCER_BIN, else target/release or target/debug of the checkout."""
    if os.environ.get("LANCER_BIN"):
        return pathlib.Path(os.environ["LANCER_BIN"])
    for profile in ("release", "debug"):
        p = REPO / "target" / profile / "lancer"
        if p.exists():
            return p
    found = shutil.which("lancer")
    return pathlib.Path(found) if found else None

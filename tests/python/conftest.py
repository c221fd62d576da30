"""The Python module's tests (pytest): they import `talkinghead` from PYTHONPATH (the installed tree in CI,
build/python in a build) and read the shared data from $TALKINGHEAD_DATA or ../shared/data."""

import os

import pytest


@pytest.fixture(scope="session")
def data():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.environ.get("TALKINGHEAD_DATA") or os.path.join(here, "..", "..", "..", "shared", "data")
    assert os.path.isdir(root), "the shared data is not at %s (set TALKINGHEAD_DATA)" % root
    return root

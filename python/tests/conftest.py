"""Shared fixtures of the Python tests: where the repository's example scenes are, and the linx
program of the same build (for comparing with `linx run`)."""

import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("LINX_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


@pytest.fixture
def examples() -> pathlib.Path:
    return SOURCE / "examples"


@pytest.fixture
def linx_program() -> str:
    from linx import _programs
    return _programs.LINX

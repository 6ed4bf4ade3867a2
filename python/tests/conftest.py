# SPDX-License-Identifier: GPL-3.0-or-later
# Shared fixtures of the Python module's tests: where the sources and the CLI are (ctest sets
# LIBSHADOW_SOURCE_DIR and LIBSHADOW_CLI; run by hand, the source tree is found from this file).
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("LIBSHADOW_SOURCE_DIR") or pathlib.Path(__file__).resolve().parents[2])


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def cli():
    """The shadow CLI; the tests that compare with it need it (ctest passes it when it is built)."""
    path = os.environ.get("LIBSHADOW_CLI")
    if not path:
        candidate = SOURCE_DIR / "build" / "release" / "bin" / "shadow"
        path = str(candidate) if candidate.exists() else ""
    if not path:
        pytest.fail("the shadow CLI was not found: set LIBSHADOW_CLI (ctest does)")
    return path

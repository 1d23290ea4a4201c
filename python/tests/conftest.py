"""Where the program is: ctest passes IMPACTID_EXECUTABLE (python/CMakeLists.txt)."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("IMPACTID_SOURCE_DIR",
                                         pathlib.Path(__file__).parents[2])).resolve()


@pytest.fixture(scope="session")
def executable() -> str:
    path = os.path.abspath(os.environ.get("IMPACTID_EXECUTABLE",
                                          SOURCE_DIR / "build" / "study" / "impactid"))
    assert os.path.exists(path), f"{path}: build impactid first (scripts/build)"
    return path


@pytest.fixture(scope="session")
def source_dir() -> pathlib.Path:
    return SOURCE_DIR


@pytest.fixture(scope="session")
def child_env() -> dict:
    """The environment of a child python3 that imports this impactid, from any folder."""
    import impactid

    package_parent = str(pathlib.Path(impactid.__file__).resolve().parents[1])
    return dict(os.environ, PYTHONPATH=package_parent)

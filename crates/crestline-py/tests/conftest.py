"""Shared fixtures: the shared meshes and quality cases, and the command-line tool.

Environment:
- ``CRESTLINE_SHARED``: the shared folder (default: ``../shared`` next to the checkout).
- ``CRESTLINE_CLI``: the ``crestline`` binary the Python API is compared with. When it is
  not set, the usual cargo output folders are searched and the comparisons are skipped if
  none has it; when it is set, it must exist (CI sets it).
"""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import crestline

CRATE = Path(__file__).resolve().parents[1]
REPO = CRATE.parents[1]
SHARED = Path(os.environ.get("CRESTLINE_SHARED", REPO.parent / "shared"))
MESHES = SHARED / "data" / "meshes"
CASES = SHARED / "quality" / "cases"
# The built-in example of the command-line tool, kept in the repository.
FANDISK = REPO / "crates" / "crestline-cli" / "data" / "fandisk.obj"


def _find_cli():
    given = os.environ.get("CRESTLINE_CLI")
    if given:
        if not Path(given).is_file():
            raise RuntimeError(f"CRESTLINE_CLI={given} does not exist")
        return Path(given)
    targets = [Path(os.environ["CARGO_TARGET_DIR"])] if "CARGO_TARGET_DIR" in os.environ else []
    targets.append(REPO / "target")
    for target in targets:
        for profile in ("release", "debug"):
            candidate = target / profile / "crestline"
            if candidate.is_file():
                return candidate
    found = shutil.which("crestline")
    return Path(found) if found else None


@pytest.fixture(scope="session")
def cli():
    path = _find_cli()
    if path is None:
        pytest.skip("no crestline binary (build it with cargo, or set CRESTLINE_CLI)")
    return path


@pytest.fixture(scope="session")
def fandisk():
    return crestline.read_mesh(FANDISK)


def case_path(case):
    """The OBJ of a quality case such as "ovoid/reg5k"; skips when the shared data is missing."""
    path = CASES / f"{case}.obj"
    if not path.is_file():
        pytest.skip(f"{path} not found (set CRESTLINE_SHARED)")
    return path


def tetrahedron():
    """A closed tetrahedron wound outward: (vertices float64, faces int64)."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int64)
    return vertices, faces

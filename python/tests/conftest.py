"""Shared fixtures: the glint CLI and the source tree (from CTest's
environment: GLINT_CLI, GLINT_SOURCE_DIR), and a small scene."""
import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(os.environ.get("GLINT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))

SMALL = """{
  "render": { "width": 40, "height": 30, "background": [0.1, 0.2, 0.3] },
  "camera": { "position": [0, 1, 6], "look_at": [0, 0.5, 0] },
  "materials": {
    "red":   { "ambient": 0.1, "diffuse": [0.8, 0.2, 0.1], "specular": 0.6, "shininess": 40 },
    "floor": { "ambient": 0.05, "diffuse": 0.5, "specular": 0.3, "shininess": 10 }
  },
  "lights": [ { "type": "point", "position": [-3, 5, 4], "ambient": 0.2 } ],
  "objects": [
    { "type": "sphere", "center": [-0.8, 0.8, 0], "radius": 0.8, "material": "red" },
    { "type": "sphere", "center": [1, 0.5, -0.5], "radius": 0.5, "material": "red" },
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor" }
  ]
}"""


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("GLINT_CLI") or shutil.which("glint")
    if not path:
        pytest.skip("the glint CLI is not known (set GLINT_CLI)")
    return path


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture
def small():
    import glint
    return glint.loads(SMALL, name="small.json")

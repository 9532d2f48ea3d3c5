"""Fixtures of the world-import tests: the shipped real worlds unpacked, and small synthetic worlds."""

from __future__ import annotations

import tarfile
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).resolve().parents[2]


def unpack(archive: Path, into: Path) -> Path:
    with tarfile.open(archive) as tar:
        tar.extractall(into, filter="data")
    return into


@pytest.fixture(scope="session")
def warehouse_models(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return unpack(DATA / "aws_small_warehouse" / "models.tar.xz", tmp_path_factory.mktemp("aws")) / "models"


@pytest.fixture(scope="session")
def house_models(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return unpack(DATA / "hunav" / "small_house_models.tar.xz", tmp_path_factory.mktemp("house")) / "media" / "models"


def world_file(folder: Path, body: str, version: str = "1.7", name: str = "w.world") -> Path:
    """A world file holding `body` inside <world>."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(f'<?xml version="1.0"?>\n<sdf version="{version}"><world name="t">{body}</world></sdf>\n')
    return path


def static_model(name: str, pose: str, geometry: str, extra: str = "") -> str:
    return (f'<model name="{name}"><static>true</static><pose>{pose}</pose><link name="l">'
            f'<collision name="c"><geometry>{geometry}</geometry></collision></link>{extra}</model>')


def occupied_world_box(location: Path) -> tuple[float, float, float, float]:
    """(xmin, ymin, xmax, ymax) in metres of the occupied and solid cells of an imported map."""
    from socnavgen.location import load_location

    loc = load_location(location)
    occ = loc.occupancy
    rows, cols = np.nonzero(occ.occupied | (occ.unknown & _inside(occ.unknown)))
    world = loc.transform.pixels_to_world(np.stack([cols, rows], axis=1))
    half = loc.transform.meters_per_pixel / 2
    return (float(world[:, 0].min() - half), float(world[:, 1].min() - half), float(world[:, 0].max() + half),
            float(world[:, 1].max() + half))


def _inside(unknown: np.ndarray) -> np.ndarray:
    """Unknown cells not connected to the map's edge (a solid's inside, not the outside)."""
    from scipy import ndimage

    labels, _ = ndimage.label(unknown)
    edge = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    return ~np.isin(labels, edge[edge > 0])

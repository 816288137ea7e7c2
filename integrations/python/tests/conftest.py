"""Shared fixtures: a gridded box target and a ball resting on its top face."""

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

import meshes  # noqa: E402


@pytest.fixture
def target():
    """A 2 x 2 x 0.5 m box, each side an 8 x 8 (top and bottom) grid: top face at z = 0.25."""
    return meshes.box()


@pytest.fixture
def ball():
    """A 0.3 m ball touching the box's top at its centre (0, 0, 0.25)."""
    return meshes.sphere(0.3, center=(0.0, 0.0, 0.55))


@pytest.fixture
def impact():
    """Head-on from above at the top's centre."""
    return dict(point=(0.0, 0.0, 0.25), normal=(0.0, 0.0, -1.0), relative_velocity=(0.0, 0.0, -3.0))


def signed_volume(positions, faces):
    """The enclosed volume of a closed, outward-wound mesh, m^3 (float64)."""
    p = positions.astype(np.float64)[faces.astype(np.int64)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)

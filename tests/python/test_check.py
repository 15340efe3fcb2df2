"""tpmsfill.check from Python: the facts of meshes made with numpy, and errors as exceptions."""
import math

import numpy as np
import pytest

import tpmsfill
from meshes import box, torus


def test_a_cube_is_valid_with_its_volume():
    v, f = box(10)
    facts = tpmsfill.check(v, f)
    assert facts["valid"] and facts["closed"] and facts["manifold"] and facts["outward"]
    assert facts["genus"] == 0
    assert facts["volume"] == pytest.approx(1000, rel=1e-12)
    assert facts["triangles"] == 12


def test_a_torus_has_genus_one_and_its_volume():
    v, f = torus(10, 3, 96, 48)
    facts = tpmsfill.check(v, f, self_intersections=False)
    assert facts["closed"] and facts["genus"] == 1
    # A polyhedral torus holds a little less than 2π²Rr² (its chords cut inside).
    assert facts["volume"] == pytest.approx(2 * math.pi**2 * 10 * 9, rel=0.01)


def test_an_open_or_flipped_mesh_says_so():
    v, f = box(10)
    open_box = tpmsfill.check(v, f[:-2])
    assert not open_box["valid"] and not open_box["closed"] and open_box["holes"] == 1
    flipped = f.copy()
    flipped[3] = flipped[3][::-1]
    assert tpmsfill.check(v, flipped)["inconsistent_edges"] > 0
    inside_out = tpmsfill.check(v, f[:, ::-1])
    assert inside_out["closed"] and not inside_out["outward"]


def test_bad_arrays_raise_the_library_errors():
    v, f = box(10)
    with pytest.raises(tpmsfill.InputError, match="vertices must be an"):
        tpmsfill.check(v[:, :2], f)
    with pytest.raises(tpmsfill.InputError, match="face 0 names vertex 99"):
        tpmsfill.check(v, np.array([[0, 1, 99]]))
    with pytest.raises(tpmsfill.Error):  # every error is a tpmsfill.Error
        tpmsfill.check(v, np.array([[0, 1, -1]]))
    assert issubclass(tpmsfill.ParseError, tpmsfill.Error)

"""tpmsfill.fill from Python: a numpy cube filled, the output's facts checked by tpmsfill.check."""
import numpy as np
import pytest

import tpmsfill
from meshes import box


def test_a_cube_fills_with_a_valid_gyroid_of_its_porosity():
    v, f = box(10)
    points, triangles, report = tpmsfill.fill(
        v, f, voxel=0.2, lattice={"type": "gyroid", "cell": 5, "porosity": 0.6})
    assert points.shape[1] == 3 and triangles.shape[1] == 3 and len(triangles) > 1000
    assert points.dtype == np.float64 and triangles.dtype == np.uint32
    assert not points.flags.owndata  # the library's own memory, not a copy
    facts = tpmsfill.check(points, triangles, self_intersections=False)
    assert facts["valid"] and facts["closed"] and facts["outward"]
    # Inside the cube, up to a voxel; the porosity asked within 3 points.
    assert points.min() >= -0.2 and points.max() <= 10.2
    assert report["valid"] and report["porosity"] == pytest.approx(0.6, abs=0.03)
    assert 1 - facts["volume"] / 1000 == pytest.approx(report["porosity"], abs=0.01)


def test_keyword_arguments_replace_the_recipes_keys():
    v, f = box(10)
    recipe = {"voxel": 0.5, "lattice": {"type": "primitive", "cell": 5}}
    _, _, coarse = tpmsfill.fill(v, f, recipe)
    _, _, fine = tpmsfill.fill(v, f, recipe, voxel=0.25)
    assert coarse["grid"]["voxel"] == pytest.approx(0.5)
    assert fine["grid"]["voxel"] == pytest.approx(0.25)
    assert recipe["voxel"] == 0.5  # the caller's dict is left as it was


def test_bad_recipes_and_models_raise_input_errors():
    v, f = box(10)
    with pytest.raises(tpmsfill.InputError, match="colour"):
        tpmsfill.fill(v, f, colour="red")
    with pytest.raises(tpmsfill.InputError):
        tpmsfill.fill(v, f, lattice={"type": "gyroid", "cell": -1})

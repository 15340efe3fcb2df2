"""The library's other jobs from Python, and progress and cancel through a callable: slice,
decimate, repair, field_fit, conformal, each judged by the facts of what it returns."""
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import tpmsfill
from meshes import box, dome

GYROID = {"voxel": 0.2, "lattice": {"type": "gyroid", "cell": 5}}


def test_progress_goes_from_zero_to_one_and_false_cancels():
    v, f = box(10)
    seen = []
    tpmsfill.fill(v, f, GYROID, progress=lambda stage, x: seen.append((stage, x)))
    fractions = [x for _, x in seen]
    assert fractions[0] == 0 and fractions[-1] == 1
    assert all(a <= b for a, b in zip(fractions, fractions[1:]))  # never goes back
    assert {"distance", "marching cubes", "validate"} <= {s for s, _ in seen}
    with pytest.raises(tpmsfill.Cancelled):
        tpmsfill.fill(v, f, GYROID, progress=lambda stage, x: x < 0.3)


def test_an_exception_in_the_callable_stops_the_job_and_is_raised():
    v, f = box(10)

    def fails(stage, x):
        if x > 0.2:
            raise ZeroDivisionError("the caller's own")

    with pytest.raises(ZeroDivisionError, match="the caller's own"):
        tpmsfill.fill(v, f, GYROID, progress=fails)


def test_ctrl_c_interrupts_a_long_fill_at_once():
    # An 18 mm cube at 0.04 mm: 91 million samples on one grid, about 4 s on two cores,
    # reporting at least every 0.7 s; interrupted after 0.5 s. (Jobs that go in slabs report
    # once a slab: seconds apart on large jobs.)
    script = (
        "import os, signal, sys, threading, time\n"
        f"sys.path.insert(0, {os.path.dirname(__file__)!r})\n"
        "import tpmsfill\n"
        "from meshes import box\n"
        "v, f = box(18)\n"
        "threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()\n"
        "t0 = time.time()\n"
        "try:\n"
        "    tpmsfill.fill(v, f, voxel=0.04, lattice={'type': 'gyroid', 'cell': 5})\n"
        "    print('finished', time.time() - t0)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', time.time() - t0)\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=120, env=dict(os.environ)).stdout.split()
    assert out and out[0] == "interrupted", out
    assert float(out[1]) < 2.5


def test_slice_layers_add_up_to_the_filled_volume():
    v, f = box(10)
    layers, report = tpmsfill.slice(v, f, 0.25, GYROID)
    assert len(layers) == 40 and report["slice"]["layers"] == 40
    assert all(a["z"] < b["z"] for a, b in zip(layers, layers[1:]))
    for layer in layers:
        for c in layer["contours"]:
            assert c.shape[1] == 2 and len(c) >= 3
            assert c.min() >= -0.2 and c.max() <= 10.2
    sliced = sum(layer["area"] for layer in layers) * 0.25
    assert sliced == pytest.approx(report["slice"]["volume"], rel=1e-9)
    points, triangles, _ = tpmsfill.fill(v, f, GYROID)
    filled = tpmsfill.check(points, triangles, self_intersections=False)["volume"]
    assert sliced == pytest.approx(filled, rel=0.02)
    # Each layer's signed areas: outer contours counter-clockwise, so they sum to the area.
    shoelace = lambda c: 0.5 * np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1])  # noqa: E731
    middle = layers[20]
    assert sum(shoelace(c) for c in middle["contours"]) == pytest.approx(middle["area"], rel=1e-6)


def test_decimate_keeps_a_valid_mesh_within_its_tolerance():
    v, f = box(10)
    points, triangles, _ = tpmsfill.fill(v, f, GYROID)
    dv, df, report = tpmsfill.decimate(points, triangles, 0.05)
    assert len(df) < 0.5 * len(triangles)
    assert tpmsfill.check(dv, df)["valid"] and report["valid"]
    assert report["hausdorff"] <= 0.05 + 1e-9


def test_repair_closes_a_box_with_a_face_missing():
    v, f = box(10)
    assert not tpmsfill.check(v, f[:-2])["valid"]
    rv, rf, report = tpmsfill.repair(v, f[:-2])
    facts = tpmsfill.check(rv, rf)
    assert facts["valid"] and facts["volume"] == pytest.approx(1000, rel=1e-6)
    with pytest.raises(tpmsfill.InputError, match="colour"):
        tpmsfill.repair(v, f, colour=1)


def test_a_field_fitted_from_numpy_fills_a_part(tmp_path):
    # A signed field of spherical pores 2 mm across on a 12 mm grid of 0.5 mm cells, negative in
    # the solid between them.
    n, h = 24, 0.5
    z, y, x = np.meshgrid(*(np.arange(n) * h + h / 2,) * 3, indexing="ij")
    centres = [(3, 3, 3), (9, 4, 6), (5, 9, 9), (2, 10, 3), (10, 10, 11)]
    pores = np.min([np.sqrt((x - a) ** 2 + (y - b) ** 2 + (z - c) ** 2) for a, b, c in centres],
                   axis=0)
    values = 2 - pores  # solid (negative) farther than 2 mm from every pore centre
    out = tmp_path / "sponge.itdf"
    fit = tpmsfill.field_fit(values, str(out), spacing=(h, h, h))
    assert out.exists() and fit["coefficients"] == (12, 12, 12)
    assert fit["rms"] < 0.05 * (values.max() - values.min())
    v, f = box(12)
    points, triangles, report = tpmsfill.fill(v, f, voxel=0.2, field=str(out))
    facts = tpmsfill.check(points, triangles, self_intersections=False)
    assert facts["valid"]
    # The pores' share of the cube (five 2 mm balls, partly cut by its faces) is about the void.
    pore_share = np.mean(values > 0)
    assert 1 - facts["volume"] / 12 ** 3 == pytest.approx(pore_share, abs=0.03)
    with pytest.raises(tpmsfill.InputError, match="signed"):
        tpmsfill.field_fit(values, str(out), sign="unknown")


def test_conformal_lays_a_layer_on_a_numpy_dome():
    v, f = dome(20, 6, 12, 48)
    points, triangles, report = tpmsfill.conformal(
        v, f, 3, voxel=0.3, lattice={"type": "gyroid", "cell": 5})
    facts = tpmsfill.check(points, triangles, self_intersections=False)
    assert facts["valid"]
    # The layer stands 0 to 3 mm above the dome, up to a voxel.
    c = report["conformal"]
    assert c["height_min"] >= -0.3 and c["height_max"] <= 3.3
    assert points[:, 2].max() <= 6 + 3 + 0.3

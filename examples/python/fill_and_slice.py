# %% [markdown]
# # A torus filled with a gyroid, from Python
#
# A notebook in percent format (Jupyter, VS Code and Spyder open the `# %%` cells as cells; it
# also runs as a script): a mesh made with numpy, filled with a lattice, the output's facts
# checked, one printer layer plotted with matplotlib. Run it after `bash scripts/test.sh`:
#
#     PYTHONPATH=build/python python3 examples/python/fill_and_slice.py [picture.png]

# %%
import math
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed; the picture is written to a file
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tpmsfill  # noqa: E402

# %% [markdown]
# ## A mesh made with numpy
# A torus around z, 24 mm across its hole's axis: major radius 12, minor radius 5, n × m quads
# split in two, counter-clockwise seen from outside.

# %%
def torus(R, r, n, m):
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    u, w = 2 * math.pi * i / n, 2 * math.pi * j / m
    v = np.stack([(R + r * np.cos(w)) * np.cos(u), (R + r * np.cos(w)) * np.sin(u),
                  r * np.sin(w)], axis=-1).reshape(-1, 3)
    idx = lambda a, b: (a % n) * m + (b % m)  # noqa: E731
    f = [[idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)] for a in range(n) for b in range(m)]
    f += [[idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)] for a in range(n) for b in range(m)]
    return v, np.array(f)


vertices, faces = torus(12, 5, 96, 48)
facts = tpmsfill.check(vertices, faces)
print(f"torus: valid {facts['valid']}, genus {facts['genus']}, volume {facts['volume']:.0f} mm³")

# %% [markdown]
# ## Filled with a gyroid at 70 % porosity
# The job is a recipe (docs/recipes.md) given as keyword arguments; progress is a callable.

# %%
def progress(stage, fraction):
    print(f"\r{stage:<16} {100 * fraction:5.1f} %", end="", flush=True)


points, triangles, report = tpmsfill.fill(
    vertices, faces, voxel=0.2, lattice={"type": "gyroid", "cell": 4, "porosity": 0.7},
    progress=progress)
print()
lattice = tpmsfill.check(points, triangles, self_intersections=False)
print(f"lattice: {len(triangles):,} triangles, valid {lattice['valid']}, "
      f"porosity {report['porosity']:.3f} (asked 0.700)")

# %% [markdown]
# ## One printer layer
# The same job sliced into 0.2 mm layers; the middle one plotted, solid filled, holes white.

# %%
layers, sliced = tpmsfill.slice(vertices, faces, 0.2, voxel=0.2,
                                lattice={"type": "gyroid", "cell": 4, "porosity": 0.7})
middle = min(layers, key=lambda layer: abs(layer["z"]))
fig, ax = plt.subplots(figsize=(6, 6))
for c in sorted(middle["contours"], key=lambda c: -abs(np.sum(
        c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1]))):
    area = 0.5 * np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1])
    ax.fill(c[:, 0], c[:, 1], color="#3b6ea5" if area > 0 else "white", linewidth=0)
ax.set_aspect("equal")
ax.set_title(f"layer at z = {middle['z']:.2f} mm: {len(middle['contours'])} contours, "
             f"{middle['area']:.0f} mm² solid")
ax.set_xlabel("x, mm")
ax.set_ylabel("y, mm")
out = sys.argv[1] if len(sys.argv) > 1 else "torus-layer.png"
fig.savefig(out, dpi=100)
print(f"layer plotted to {out}")

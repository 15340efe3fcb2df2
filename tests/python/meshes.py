"""Meshes made with numpy for the tests: (vertices, faces), outward."""
import math

import numpy as np


def box(size):
    """A closed cube of side `size` mm, outward, as (vertices, faces)."""
    v = np.array([[x, y, z] for z in (0, size) for y in (0, size) for x in (0, size)], float)
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return v, f


def torus(R, r, n, m):
    """A closed torus of n × m quads, each split in two, outward."""
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    u, w = 2 * math.pi * i / n, 2 * math.pi * j / m
    v = np.stack([(R + r * np.cos(w)) * np.cos(u), (R + r * np.cos(w)) * np.sin(u),
                  r * np.sin(w)], axis=-1).reshape(-1, 3)
    idx = lambda a, b: (a % n) * m + (b % m)  # noqa: E731
    f = []
    for a in range(n):
        for b in range(m):
            f += [[idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)],
                  [idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)]]
    return v, np.array(f)

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


def dome(radius, height, rings, segments):
    """An open spherical cap over a disk of `radius` rising `height` at its centre, normals up."""
    pts = [[0.0, 0.0, height]]
    for a in range(1, rings + 1):
        r = radius * a / rings
        for b in range(segments):
            t = 2 * math.pi * b / segments
            pts.append([r * math.cos(t), r * math.sin(t), height * (1 - (r / radius) ** 2)])
    f = [[0, 1 + b, 1 + (b + 1) % segments] for b in range(segments)]
    for a in range(1, rings):
        inner, outer = 1 + (a - 1) * segments, 1 + a * segments
        for b in range(segments):
            c = (b + 1) % segments
            f += [[inner + b, outer + b, outer + c], [inner + b, outer + c, inner + c]]
    return np.array(pts), np.array(f)

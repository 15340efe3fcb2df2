#!/usr/bin/env python3
"""Seed 004's procedural stand-in surfaces, as OFF files, for scripts/catalogue.sh and
scripts/bench.sh: python3 scripts/surfaces.py OUT_DIR

  hemisphere.off  the upper half of a sphere of radius 30 mm (rings of latitude), normals out
  wave.off        z = 6 sin(2 pi x / 40) sin(2 pi y / 40) over [0, 80]^2 mm, normals up
"""
import math
import os
import sys


def write_off(path, points, triangles):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(points), len(triangles)))
        for p in points:
            f.write("%.9f %.9f %.9f\n" % p)
        for t in triangles:
            f.write("3 %d %d %d\n" % t)


def hemisphere(radius=30.0, rings=40, segments=160):
    points = [(0.0, 0.0, radius)]
    for r in range(1, rings + 1):
        theta = 0.5 * math.pi * r / rings
        for k in range(segments):
            phi = 2 * math.pi * k / segments
            points.append((radius * math.sin(theta) * math.cos(phi),
                           radius * math.sin(theta) * math.sin(phi), radius * math.cos(theta)))

    def vid(r, k):
        return 1 + (r - 1) * segments + k % segments

    triangles = [(0, vid(1, k), vid(1, k + 1)) for k in range(segments)]
    for r in range(1, rings):
        for k in range(segments):
            triangles.append((vid(r, k), vid(r + 1, k), vid(r + 1, k + 1)))
            triangles.append((vid(r, k), vid(r + 1, k + 1), vid(r, k + 1)))
    return points, triangles


def wave(size=80.0, n=120, amplitude=6.0, wavelength=40.0):
    points = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = size * i / n, size * j / n
            z = amplitude * math.sin(2 * math.pi * x / wavelength) * math.sin(2 * math.pi * y / wavelength)
            points.append((x, y, z))

    def vid(i, j):
        return i + (n + 1) * j

    triangles = []
    for j in range(n):
        for i in range(n):
            triangles.append((vid(i, j), vid(i + 1, j), vid(i + 1, j + 1)))
            triangles.append((vid(i, j), vid(i + 1, j + 1), vid(i, j + 1)))
    return points, triangles


if __name__ == "__main__":
    out = sys.argv[1]
    write_off(os.path.join(out, "hemisphere.off"), *hemisphere())
    write_off(os.path.join(out, "wave.off"), *wave())

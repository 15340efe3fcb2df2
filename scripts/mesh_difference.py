#!/usr/bin/env python3
"""How far apart two meshes of one part are: for changes that are meant to move a mesh only by
rounding (a different solver, a different summation order), measured rather than assumed.

  python3 scripts/mesh_difference.py BEFORE.stl AFTER.stl [VOXEL_MM]

Reads binary STL (what every tpmsfill job writes by default). Prints, for each mesh, its
triangles, distinct vertices, signed volume and area, then the largest distance from a vertex
of either mesh to the nearest vertex of the other (a vertex Hausdorff distance, exact over the
vertices, searched in a hash grid), also in voxels when VOXEL_MM is given."""
import math
import struct
import sys


def read_stl(path):
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        sys.exit(f"{path}: {e.strerror}")
    if len(data) < 84:
        sys.exit(f"{path}: {len(data)} bytes, too short for a binary STL (84 at least)")
    n = struct.unpack_from("<I", data, 80)[0]
    if len(data) != 84 + 50 * n:
        sys.exit(f"{path}: not a binary STL of {n} triangles")
    tris = []
    for i in range(n):
        v = struct.unpack_from("<9f", data, 84 + 50 * i + 12)
        tris.append((v[0:3], v[3:6], v[6:9]))
    return tris


def facts(tris):
    vol = area = 0.0
    points = set()
    for a, b, c in tris:
        points.update((a, b, c))
        ab = [b[k] - a[k] for k in range(3)]
        ac = [c[k] - a[k] for k in range(3)]
        cr = (ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0])
        area += 0.5 * math.sqrt(sum(x * x for x in cr))
        vol += sum(a[k] * cr[k] for k in range(3)) / 6
    return points, vol, area


def farthest(from_points, to_points, cell):
    grid = {}
    for p in to_points:
        grid.setdefault(tuple(int(math.floor(x / cell)) for x in p), []).append(p)
    worst = 0.0
    for p in from_points:
        key = tuple(int(math.floor(x / cell)) for x in p)
        best = math.inf
        for r in range(0, 64):  # rings of cells until the nearest is certainly found
            for dx in range(-r, r + 1):
                for dy in range(-r, r + 1):
                    for dz in range(-r, r + 1):
                        if max(abs(dx), abs(dy), abs(dz)) != r:
                            continue
                        for q in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ()):
                            best = min(best, math.dist(p, q))
            if best <= r * cell:
                break
        if best == math.inf:  # nothing within 64 cells: look at every vertex
            best = min((math.dist(p, q) for q in to_points), default=math.inf)
        worst = max(worst, best)
    return worst


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__.split("\n\n")[1])
    a, b = read_stl(sys.argv[1]), read_stl(sys.argv[2])
    voxel = float(sys.argv[3]) if len(sys.argv) > 3 else None
    pa, va, aa = facts(a)
    pb, vb, ab = facts(b)
    for name, t, p, v, s in ((sys.argv[1], a, pa, va, aa), (sys.argv[2], b, pb, vb, ab)):
        print(f"{name}: {len(t)} triangles, {len(p)} vertices, volume {v:.9g} mm3, area {s:.9g} mm2")
    relative = f" ({(vb - va) / va:+.2e})" if va else ""
    print(f"volume change {vb - va:+.3g} mm3{relative}, area change {ab - aa:+.3g} mm2")
    if not pa or not pb:
        sys.exit("one mesh has no vertices: nothing to measure the other against")
    cell = voxel or 0.1
    d = max(farthest(pa - pb, pb, cell), farthest(pb - pa, pa, cell))
    print(f"vertices in one mesh only: {len(pa - pb)} and {len(pb - pa)}; farthest from the other "
          f"mesh's vertices: {d:.3g} mm" + (f" ({d / voxel:.3g} voxels)" if voxel else ""))


if __name__ == "__main__":
    main()

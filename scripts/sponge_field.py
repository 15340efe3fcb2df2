#!/usr/bin/env python3
"""A sponge-like distance field in the seed's text form (docs/formats.md): 48³ cells of the
unit cube, each the distance to the nearest of 40 random pore centres (seed 7) minus 0.11,
signed (negative in the pores). Used by scripts/catalogue.sh and scripts/bench.sh.

    python3 scripts/sponge_field.py OUT.tdf [SIZE_MM]
"""
import math
import random
import sys

random.seed(7)
pores = [(random.random(), random.random(), random.random()) for _ in range(40)]
n = 48
with open(sys.argv[1], "w") as f:
    f.write("tpmsfill-field 1\n")
    if len(sys.argv) > 2:
        f.write("size %s %s %s\n" % ((sys.argv[2],) * 3))
    f.write("sign signed\n%d %d %d\n" % (n, n, n))
    for k in range(n):
        for j in range(n):
            p = [((i + .5) / n, (j + .5) / n, (k + .5) / n) for i in range(n)]
            f.write(" ".join("%.5f" % (min(math.dist(q, c) for c in pores) - 0.11) for q in p) + "\n")

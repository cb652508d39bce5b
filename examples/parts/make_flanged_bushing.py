#!/usr/bin/env python3
"""Writes flanged_bushing.stl: a bore of 10 mm radius through a 30 mm flange (6 mm thick)
and an 18 mm body up to 30 mm, as a closed surface of revolution (binary STL, mm)."""
import math
import struct
import sys

PROFILE = [(10.0, 0.0), (30.0, 0.0), (30.0, 6.0), (18.0, 6.0), (18.0, 30.0), (10.0, 30.0)]
SEGMENTS = 96


def main(path):
    ring = [(math.cos(2 * math.pi * k / SEGMENTS), math.sin(2 * math.pi * k / SEGMENTS))
            for k in range(SEGMENTS)]
    tris = []
    n = len(PROFILE)
    for i in range(n):
        (r0, z0), (r1, z1) = PROFILE[i], PROFILE[(i + 1) % n]
        for k in range(SEGMENTS):
            (c0, s0), (c1, s1) = ring[k], ring[(k + 1) % SEGMENTS]
            a = (r0 * c0, r0 * s0, z0)
            b = (r1 * c0, r1 * s0, z1)
            c = (r1 * c1, r1 * s1, z1)
            d = (r0 * c1, r0 * s1, z0)
            # The profile runs counter-clockwise in (r, z): the outside is on its right, so
            # (a, d, c) and (a, c, b) face outward.
            tris.append((a, d, c))
            tris.append((a, c, b))
    with open(path, "wb") as f:
        f.write(b"maxslice example: flanged bushing".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "flanged_bushing.stl")

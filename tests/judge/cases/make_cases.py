#!/usr/bin/env python3
"""Writes the hand-built ASCII STL cases of the CGAL judge (tests/judge/cases/*.stl).
Every coordinate is an integer or a multiple of 1/1024 small enough to be exact in float32,
so the STL text is read exactly. Run from anywhere: python3 tests/judge/cases/make_cases.py"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def fmt(v):
    if v == int(v):
        return str(int(v))
    return repr(float(v))  # dyadic with few bits: the decimal is exact


def write(name, tris):
    with open(os.path.join(HERE, name + '.stl'), 'w') as f:
        f.write('solid %s\n' % name)
        for t in tris:
            f.write('facet normal 0 0 0\nouter loop\n')
            for p in t:
                f.write('vertex %s %s %s\n' % tuple(fmt(c) for c in p))
            f.write('endloop\nendfacet\n')
        f.write('endsolid %s\n' % name)


def box(x0, y0, z0, x1, y1, z1):
    """12 outward triangles; every square split along the diagonal from its first corner."""
    c = lambda i, j, k: ((x0, x1)[i], (y0, y1)[j], (z0, z1)[k])
    quads = [
        (c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)),  # z0, normal -z
        (c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)),  # z1, +z
        (c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)),  # y0, -y
        (c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)),  # y1, +y
        (c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)),  # x0, -x
        (c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)),  # x1, +x
    ]
    out = []
    for a, b, cc, d in quads:
        out += [(a, b, cc), (a, cc, d)]
    return out


def flip(tris):
    return [(t[0], t[2], t[1]) for t in tris]


def tetra(a, b, c, d):
    return [(a, c, b), (a, b, d), (b, c, d), (c, a, d)]


def torus(R, r, n, m, q=1024):
    rnd = lambda v: round(v * q) / q
    P = lambda i, j: tuple(rnd(v) for v in (
        (R + r * math.cos(2 * math.pi * j / m)) * math.cos(2 * math.pi * i / n),
        (R + r * math.cos(2 * math.pi * j / m)) * math.sin(2 * math.pi * i / n),
        r * math.sin(2 * math.pi * j / m)))
    out = []
    for i in range(n):
        for j in range(m):
            a, b, c, d = P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)
            out += [(a, b, c), (a, c, d)]
    return out


cases = {
    # Two 20 mm cubes overlapping by a 10 mm cube (the slicer test file).
    'overlapping_cubes': box(0, 0, 0, 20, 20, 20) + box(10, 10, 10, 30, 30, 30),
    # Two cubes pressed face to face, offset so the faces share area but no vertex.
    'touching_cubes_offset': box(0, 0, 0, 10, 10, 10) + box(10, 5, 5, 20, 15, 15),
    # Two cubes face to face with the same corners: the two faces are duplicate pairs
    # (opposite orientation), never intersecting pairs.
    'touching_cubes_flush': box(0, 0, 0, 10, 10, 10) + box(10, 0, 0, 20, 10, 10),
    # A tetrahedron whose apex is pushed through the opposite face: every two faces share an
    # edge and are not coplanar, so by the definition nothing intersects (it is inside out).
    'tetra_pushed': tetra((0, 0, 0), (10, 0, 0), (0, 10, 0), (2, 2, -5)),
    # A cube whose corner (10,10,10) is pushed through the bottom face, to (4,6,-3).
    'cube_corner_pushed': [tuple((4, 6, -3) if p == (10, 10, 10) else p for p in t)
                           for t in box(0, 0, 0, 10, 10, 10)],
    # A fold-over across a shared edge: (a,b,c) and (b,a,d) with c, d on the same side of ab;
    # then a proper neighbour across the edge ac (not a fold).
    'fold_over': [((0, 0, 0), (10, 0, 0), (0, 10, 0)), ((10, 0, 0), (0, 0, 0), (3, 4, 0)),
                  ((0, 0, 0), (0, 10, 0), (-5, 5, 0))],
    # A T-junction: a vertical triangle standing with one edge inside a horizontal one.
    't_junction': [((0, 0, 0), (10, 0, 0), (0, 10, 0)), ((2, 2, 0), (5, 2, 0), (3, 2, 5))],
    # A needle (three distinct collinear corners) crossing a triangle, a degenerate triangle
    # (a repeated corner), and a proper triangle.
    'needle': [((0, 0, -5), (0, 0, 1), (0, 0, 5)), ((-5, -5, 0), (5, -5, 0), (0, 5, 0)),
               ((1, 1, 1), (1, 1, 1), (2, 3, 4))],
    # Duplicates: a group of three (same, same, opposite: mixed), a group of two opposite,
    # and a triangle crossing every member of the first group.
    'duplicates': [((0, 0, 0), (10, 0, 0), (0, 10, 0)), ((10, 0, 0), (0, 10, 0), (0, 0, 0)),
                   ((0, 0, 0), (0, 10, 0), (10, 0, 0)),
                   ((20, 0, 0), (30, 0, 0), (20, 10, 0)), ((20, 0, 0), (20, 10, 0), (30, 0, 0)),
                   ((2, 2, -3), (3, 2, 3), (2, 3, 3))],
    # Two tetrahedra passing through each other.
    'interpenetrating_tetrahedra': tetra((0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10))
                                   + tetra((3, 3, 3), (13, 3, 3), (3, 13, 3), (3, 3, -7)),
    # Coplanar contacts without area (touching), and one with area (coplanar):
    # meeting at a point, along a segment, and overlapping.
    'coplanar_contacts': [((0, 0, 0), (10, 0, 0), (0, 10, 0)), ((5, 5, 0), (15, 5, 0), (15, 15, 0)),
                          ((30, 0, 0), (40, 0, 0), (30, 10, 0)), ((32, 0, 0), (38, 0, 0), (35, -5, 0)),
                          ((60, 0, 0), (70, 0, 0), (60, 10, 0)), ((62, 1, 0), (66, 1, 0), (62, 5, 0))],
    # A cube with an inward cavity and a cube inside a cube, both outward: nothing intersects.
    'nested_cubes': box(0, 0, 0, 30, 30, 30) + flip(box(10, 10, 10, 20, 20, 20))
                    + box(40, 0, 0, 70, 30, 30) + box(50, 10, 10, 60, 20, 20),
    # A clean torus: many shared-vertex and shared-edge neighbours, no pair.
    'torus': torus(20, 7, 48, 24),
}

if __name__ == '__main__':
    for name, tris in cases.items():
        write(name, tris)
    print('wrote %d cases to %s' % (len(cases), HERE))

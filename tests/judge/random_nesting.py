#!/usr/bin/env python3
"""stltopo's shell nesting (`parent`, `depth`), orientation and `solid` against an answer
computed here, on random scenes of closed shells: boxes, tetrahedra, non-convex voxel shapes
and non-convex bipyramids with sloped faces on a small integer grid, some turned inside out, nested, apart, or sharing a corner, then moved
far from the origin (2^20) or shrunk (2^-20). Integer grids put many corners of one shell
exactly in the planes, on the lines and at the heights of another's edges and corners: the
cases where a point-in-solid test by rays has to decide ties.

The answer, from the definitions of issue 21 (README, *Geometry*): shell A lies in shell B when
every vertex of A is strictly inside the solid B bounds (for a convex shell: strictly on the
inner side of each face's plane, by exact integer orientations; for a voxel shape: every cube
whose closed box holds the point is filled; for a bipyramid: in a closed tetrahedron from its
centre over a face, and on no face); `depth` counts the shells A
lies in, `parent` is the innermost of them; `solid` holds when every shell is outward at even
depth and inward at odd depth, and nothing else is wrong. Scenes where the CGAL judge finds an
intersecting pair, a zero-area or a duplicate triangle are skipped (nesting is only defined for
shells that intersect no other), as are those where two shapes share a side (one shell then).

  random_nesting.py STLTOPO_CLI JUDGE [--cases N] [--seed S] [--keep DIR]
"""
import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from random_agree import box, write_binary  # noqa: E402


def orient(a, b, c, d):
    """Sign of det[b - a, c - a, d - a] (integers: exact)."""
    bx, by, bz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    cx, cy, cz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    dx, dy, dz = d[0] - a[0], d[1] - a[1], d[2] - a[2]
    v = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx)
    return (v > 0) - (v < 0)


def tetra(r, lo, hi):
    while True:
        p = [tuple(r.randint(lo[k], hi[k]) for k in range(3)) for _ in range(4)]
        o = orient(*p)
        if o:
            break
    a, b, c, d = p
    if o < 0:
        b, c = c, b
    # orient(a, b, c, d) > 0: d is on the positive side of (a, b, c), so outward faces are
    # the ones whose fourth corner is on their negative side
    return [(a, c, b), (a, b, d), (b, c, d), (c, a, d)]


def strictly_inside(p, tris):
    """p strictly inside the convex closed outward shell tris."""
    return all(orient(t[0], t[1], t[2], p) < 0 for t in tris)


def blob(r, lo, hi):
    """A face-connected set of cubic voxels of side 4 in [lo, hi] (None when no room), as its
    boundary's outward triangles and its exact strict-interior test. A point is strictly inside
    the union when every voxel whose closed cube holds it is filled."""
    s = 4
    dims = [min(4, (hi[k] - lo[k]) // s) for k in range(3)]
    if min(dims) < 1:
        return None
    n = [r.randint(1, d) for d in dims]
    o = [r.randint(lo[k], hi[k] - n[k] * s) for k in range(3)]
    start = tuple(r.randrange(n[k]) for k in range(3))
    full = {start}
    want = max(1, int(n[0] * n[1] * n[2] * r.uniform(0.4, 0.9)))
    steps = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    for _ in range(200):
        if len(full) >= want:
            break
        v = r.choice(sorted(full))
        d = r.choice(steps)
        w = tuple(v[k] + d[k] for k in range(3))
        if all(0 <= w[k] < n[k] for k in range(3)):
            full.add(w)
    tris = []
    # box()'s quads in order: -z, +z, -y, +y, -x, +x
    dirs = [(0, 0, -1), (0, 0, 1), (0, -1, 0), (0, 1, 0), (-1, 0, 0), (1, 0, 0)]
    for v in sorted(full):
        a = [o[k] + v[k] * s for k in range(3)]
        b = [a[k] + s for k in range(3)]
        faces = box(a, b, r)
        for q, d in enumerate(dirs):
            if tuple(v[k] + d[k] for k in range(3)) not in full:
                tris += faces[2 * q:2 * q + 2]

    def inside(p):
        choices = []
        for k in range(3):
            u = p[k] - o[k]
            choices.append([u // s] if u % s else [u // s - 1, u // s])
        return all((x, y, z) in full for x in choices[0] for y in choices[1] for z in choices[2])

    inside.nonconvex = True
    # places for a shape strictly inside: a filled voxel, or two face neighbours, less 1 a side
    inside.cells = []
    for v in sorted(full):
        a = [o[k] + v[k] * s for k in range(3)]
        inside.cells.append(([c + 1 for c in a], [c + s - 1 for c in a]))
        for d in steps[::2]:
            w = tuple(v[k] + d[k] for k in range(3))
            if w in full:
                inside.cells.append(([c + 1 for c in a], [a[k] + s - 1 + s * d[k] for k in range(3)]))
    return tris, inside, (o, [o[k] + n[k] * s for k in range(3)])


def orient2(a, b, c):
    v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (v > 0) - (v < 0)


def star(r, lo, hi):
    """A non-convex bipyramid with sloped faces: a star-shaped polygon of 5-9 corners around an
    axis parallel to z (integer corners, random radii), joined to an apex above and below. It is
    star-shaped from its centre c, so its solid is the union of the tetrahedra (c, face): a point
    is strictly inside when it lies in one of them (closed) and on no face. None when there is
    no room or the polygon is not star-shaped from c."""
    rmax = min((hi[0] - lo[0]) // 2, (hi[1] - lo[1]) // 2, 12)
    h = (hi[2] - lo[2]) // 2
    if rmax < 3 or h < 1:
        return None
    c = [r.randint(lo[k] + rmax, hi[k] - rmax) for k in range(2)] + [r.randint(lo[2] + h, hi[2] - h)]
    k = r.randint(5, 9)
    ring = []
    for i in range(k):
        a = 2 * math.pi * (i + r.uniform(-0.3, 0.3)) / k
        rad = r.uniform(1.5, rmax)
        ring.append((c[0] + round(rad * math.cos(a)), c[1] + round(rad * math.sin(a)), c[2]))
    if any(orient2(c, ring[i], ring[(i + 1) % k]) <= 0 for i in range(k)):
        return None
    top = (c[0], c[1], c[2] + r.randint(1, h))
    bottom = (c[0], c[1], c[2] - r.randint(1, h))
    tris = []
    for i in range(k):
        a, b = ring[i], ring[(i + 1) % k]
        tris += [(top, a, b), (bottom, b, a)]  # counter-clockwise ring: outward
    centre = tuple(c)

    def inside(p):
        for t in tris:
            # in the face's plane and in the cone from the centre (off that plane) over the face:
            # on the face, so not strictly inside
            if orient(t[0], t[1], t[2], p) == 0:
                n = [orient(t[i], t[(i + 1) % 3], centre, p) for i in range(3)]
                if all(x <= 0 for x in n) or all(x >= 0 for x in n):
                    return False
        for t in tris:
            # in the closed tetrahedron (t, centre): each corner replaced by p keeps the
            # orientation's sign or gives 0 (the four volumes add up to the tetrahedron's)
            s = [orient(p, t[1], t[2], centre), orient(t[0], p, t[2], centre),
                 orient(t[0], t[1], p, centre), orient(t[0], t[1], t[2], p)]
            if all(x <= 0 for x in s) or all(x >= 0 for x in s):
                return True
        return False

    inside.nonconvex = True
    inside.cells = [([v - 1 for v in centre], [v + 1 for v in centre])]
    return tris, inside, None


def scene(r):
    """Shapes in a region, each either anywhere in it or within an earlier box's inside (so that
    nesting happens often), on a grid whose planes the shapes share."""
    g = r.choice([8, 12, 16, 24])
    shapes = []  # (outward triangles, inward?, the box's (lo, hi) or None, strict-interior test)
    cells = 0
    for _ in range(r.randint(2, 6)):
        # a region of its own along x (apart from the others, or sharing their planes) ...
        x0 = cells * (g + r.choice([0, 1, 2, 2]))
        lo, hi = [x0, 0, 0], [x0 + g, g, g]
        if r.random() < 0.2:  # ... or where the others are
            lo, hi = [0, 0, 0], [g, g, g]
        else:
            cells += 1
        boxes = [s[2] for s in shapes if s[2] and all(h - l >= 3 for l, h in zip(*s[2]))]
        if boxes and r.random() < 0.7:  # strictly inside an earlier box, or touching it inside
            blo, bhi = r.choice(boxes)
            m = 1 if r.random() < 0.85 else 0
            lo, hi = [l + m for l in blo], [h - m for h in bhi]
        places = [c for sh in shapes for c in getattr(sh[3], 'cells', [])]
        if places and r.random() < 0.5:  # inside a voxel shape (maybe across a face between two
            lo, hi = r.choice(places)    # voxels), or around a star's centre
        pick = r.random()
        made = blob(r, lo, hi) if pick < 0.3 else star(r, lo, hi) if pick < 0.45 else None
        if made:
            tris, inside, rng = made
            shapes.append((tris, r.random() < 0.35, rng, inside))
        elif r.random() < 0.6:
            if r.random() < 0.5:  # a large box: room for others inside
                a = [r.randint(lo[k], lo[k] + (hi[k] - lo[k]) // 4) for k in range(3)]
                b = [r.randint(hi[k] - (hi[k] - lo[k]) // 4, hi[k]) for k in range(3)]
            else:
                a = [r.randint(lo[k], hi[k] - 1) for k in range(3)]
                b = [r.randint(a[k] + 1, hi[k]) for k in range(3)]
            t = box(a, b, r)
            shapes.append((t, r.random() < 0.35, (a, b), lambda p, t=t: strictly_inside(p, t)))
        else:
            t = tetra(r, lo, hi)
            shapes.append((t, r.random() < 0.35, None, lambda p, t=t: strictly_inside(p, t)))
    return shapes


def expected(shapes):
    n = len(shapes)
    verts = [sorted({p for t in s[0] for p in t}) for s in shapes]
    inside = [[j != i and all(shapes[j][3](p) for p in verts[i]) for j in range(n)]
              for i in range(n)]
    depth = [sum(inside[i]) for i in range(n)]
    parent = []
    for i in range(n):
        cands = [j for j in range(n) if inside[i][j]]
        parent.append(max(cands, key=lambda j: depth[j]) if cands else None)
    orientation = ['inward' if s[1] else 'outward' for s in shapes]
    shared = len({p for v in verts for p in v}) != sum(len(v) for v in verts)
    solid = not shared and all((o == 'outward') == (d % 2 == 0) for o, d in zip(orientation, depth))
    return parent, depth, orientation, solid


def move(r, tris):
    """Moves a scene far from the origin (2^18-2^20), or shrinks it (2^-10, 2^-20), or leaves it."""
    how = r.random()
    if how < 0.25:
        off = tuple(r.choice([1 << 20, -(1 << 20), 1 << 18]) for _ in range(3))
        return [tuple(tuple(c + o for c, o in zip(p, off)) for p in t) for t in tris]
    if how < 0.5:
        s = 2.0 ** -r.choice([10, 20])
        return [tuple(tuple(c * s for c in p) for p in t) for t in tris]
    return tris


def clean(cli, judge, f, shapes, extra=()):
    """stltopo's `info --json --shells` (and `extra`) of the scene file f, or None when the judge
    finds an intersecting pair, a zero-area or a duplicate triangle in it, or a shape is not one
    closed manifold shell of its own (two shapes share a side, or a voxel shape's cubes meet at
    an edge or a corner only)."""
    j = subprocess.run([judge, '--count-only', f], capture_output=True, text=True, check=True)
    head = json.loads(j.stdout.splitlines()[0])
    if head['pairs'] or head['zeroArea'] or head['duplicateGroups']:
        return None
    s = subprocess.run([cli, 'info', '--json', '--shells', *extra, f], capture_output=True, text=True, check=True)
    got = json.loads(s.stdout)
    if got['shells'] != len(shapes) or any(
            not sh['closed'] or not sh['manifold'] or sh['triangles'] != len(shapes[k][0])
            for k, sh in enumerate(got['shellList'])):
        return None
    return got


def report(f, problems, keep):
    """Prints what differs in file f and copies it into KEEP (when given): 1 when anything does."""
    if not problems:
        return 0
    print('%s: %s' % (f, '; '.join(problems)))
    if keep:
        os.makedirs(keep, exist_ok=True)
        shutil.copy(f, keep)
    return 1


def arguments(doc):
    """The command line of the random scene scripts: CLI JUDGE [--cases N] [--seed S] [--keep DIR]."""
    ap = argparse.ArgumentParser(description=doc)
    ap.add_argument('cli')
    ap.add_argument('judge')
    ap.add_argument('--cases', type=int, default=200)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--keep')
    return ap.parse_args()


def main():
    a = arguments(__doc__)
    r = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix='random_nesting.')
    bad = compared = nested = solids = in_nonconvex = 0
    try:
        for i in range(a.cases):
            shapes = scene(r)
            tris = []
            for s, inward, _, _ in shapes:
                tris += [(t[0], t[2], t[1]) for t in s] if inward else s
            tris = move(r, tris)
            f = os.path.join(tmp, 'nest%05d.stl' % i)
            write_binary(f, tris)
            got = clean(a.cli, a.judge, f, shapes, ['--intersections'])
            if got is None:
                continue
            parent, depth, orientation, solid = expected(shapes)
            compared += 1
            nested += any(d > 0 for d in depth)
            solids += solid
            in_nonconvex += any(p is not None and getattr(shapes[p][3], 'nonconvex', False) for p in parent)
            problems = []
            for k, sh in enumerate(got['shellList']):
                want = (parent[k], depth[k], orientation[k])
                have = (sh['parent'], sh['depth'], sh['orientation'])
                if want != have:
                    problems.append('shell %d: (parent, depth, orientation) %r, expected %r' % (k, have, want))
            if got['solid'] != solid:
                problems.append('solid %r, expected %r' % (got['solid'], solid))
            bad += report(f, problems, a.keep)
    finally:
        shutil.rmtree(tmp)
    print('random_nesting: %d scenes (seed %d), %d compared, %d with nesting (%d in a non-convex shape), '
          '%d solid, %d differ' % (a.cases, a.seed, compared, nested, in_nonconvex, solids, bad))
    return 1 if bad or compared == 0 else 0


if __name__ == '__main__':
    sys.exit(main())

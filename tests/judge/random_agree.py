#!/usr/bin/env python3
"""stltopo against the CGAL judge on random small soups built to hit the cases a filter gets
wrong: corners on a tiny integer grid (shared planes, collinear and coplanar contacts, repeated
and duplicate triangles), neighbours across a shared vertex or edge, the same shapes moved far
from the origin (2^20) or shrunk (multiples of 2^-20), and nearly degenerate triangles (corners
of up to 2^22 one unit off a line or a plane, where a double-precision filter cannot decide).
Every coordinate is exact in float32, so both programs read the same points.

  random_agree.py STLTOPO_CLI JUDGE [--cases N] [--seed S] [--keep DIR] [--threads T]

Each case is compared as agree.py compares a fixture (zero-area triangles, duplicate groups,
intersecting pairs and their kinds). With --threads T, stltopo's answer on T threads must also
be the same bytes as on one. Exit 1 when any case differs; --keep DIR keeps the differing files.
"""
import argparse
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import agree  # noqa: E402  (the comparison of one file)


def write_binary(path, tris):
    with open(path, 'wb') as f:
        f.write(b'random_agree'.ljust(80, b' '))
        f.write(struct.pack('<I', len(tris)))
        for t in tris:
            f.write(struct.pack('<3f', 0, 0, 0))
            for p in t:
                f.write(struct.pack('<3f', *p))
            f.write(b'\0\0')


def grid_point(r, g):
    return tuple(r.randint(0, g) for _ in range(3))


def grid_soup(r):
    g = r.choice([1, 2, 2, 3, 4, 6])
    pts = [grid_point(r, g) for _ in range(r.randint(3, 10))]
    tris = []
    for _ in range(r.randint(2, 14)):
        t = tuple(r.choice(pts) for _ in range(3))
        tris.append(t)
    return tris


def neighbours(r):
    """A base triangle and triangles sharing a corner or a side of it, or of each other."""
    g = r.choice([2, 3, 4, 8])
    tris = [tuple(grid_point(r, g) for _ in range(3))]
    for _ in range(r.randint(1, 10)):
        base = r.choice(tris)
        q = grid_point(r, g)
        if r.random() < 0.5:  # shares a side, either way round
            i = r.randrange(3)
            a, b = base[i], base[(i + 1) % 3]
            tris.append((b, a, q) if r.random() < 0.7 else (a, b, q))
        else:  # shares a corner
            tris.append((r.choice(base), q, grid_point(r, g)))
        if r.random() < 0.1:  # a copy, same or opposite way
            c = r.choice(tris)
            tris.append(c if r.random() < 0.5 else (c[0], c[2], c[1]))
    return tris


def box(lo, hi, r):
    """A box's 12 outward triangles, each square split along a diagonal r picks."""
    c = lambda i, j, k: ((lo[0], hi[0])[i], (lo[1], hi[1])[j], (lo[2], hi[2])[k])
    quads = [(c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)), (c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)),
             (c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)), (c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)),
             (c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)), (c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1))]
    out = []
    for a, b, cc, d in quads:
        out += [(a, b, cc), (a, cc, d)] if r.random() < 0.5 else [(a, b, d), (b, cc, d)]
    return out


def boxes(r):
    """Two or three boxes and tetrahedra on a small grid: flush, offset, nested, crossing."""
    tris = []
    for _ in range(r.randint(2, 3)):
        if r.random() < 0.7:
            lo = [r.randint(0, 3) for _ in range(3)]
            hi = [l + r.randint(1, 3) for l in lo]
            tris += box(lo, hi, r)
        else:
            a, b, c, d = (grid_point(r, 4) for _ in range(4))
            tris += [(a, c, b), (a, b, d), (b, c, d), (c, a, d)]
    r.shuffle(tris)
    return tris


def near_degenerate(r):
    """Corners of up to 2^22 with a third corner one unit off the line of the other two, and
    triangles one unit off the plane of another: orientations a filter cannot decide."""
    m = 1 << 22
    big = lambda: tuple(r.randint(-m, m) for _ in range(3))
    tris = []
    for _ in range(r.randint(2, 6)):
        a, b = big(), big()
        k = r.randint(1, 7)
        # a point on the segment a..b when (b - a) is divisible by 8, moved by at most 1
        b = tuple(ai + ((bi - ai) // 8) * 8 for ai, bi in zip(a, b))
        on = tuple(ai + (bi - ai) // 8 * k for ai, bi in zip(a, b))
        c = tuple(v + r.choice([-1, 0, 0, 1]) for v in on)
        tris.append((a, b, c))
    # triangles across or against a plane of the earlier ones, nearly in it
    for _ in range(r.randint(1, 6)):
        a, b, c = r.choice(tris)
        u = r.randint(1, 7)
        w = r.randint(1, 8 - u) if u < 8 else 0
        p = tuple(ai + ((bi - ai) * u + (ci - ai) * w) // 8 for ai, bi, ci in zip(a, b, c))
        q = tuple(v + r.choice([-1, 0, 1]) for v in p)
        d = big()
        e = tuple(2 * qi - di for qi, di in zip(q, d))
        if max(abs(v) for v in e) <= (1 << 24) - 1:
            tris.append((d, e, r.choice((a, b, c))))
            tris.append((q, d, big()))
    return tris


def transform(r, tris):
    """Moves a small-grid case far from the origin, or shrinks it, keeping it exact in float32."""
    how = r.random()
    if how < 0.25:
        off = tuple(r.choice([1 << 20, -(1 << 20), 0, 1 << 18]) for _ in range(3))
        return [tuple(tuple(c + o for c, o in zip(p, off)) for p in t) for t in tris]
    if how < 0.5:
        s = 2.0 ** -r.choice([10, 20, 30])
        return [tuple(tuple(c * s for c in p) for p in t) for t in tris]
    return tris


def make(r):
    kind = r.random()
    if kind < 0.3:
        return transform(r, grid_soup(r))
    if kind < 0.6:
        return transform(r, neighbours(r))
    if kind < 0.85:
        return transform(r, boxes(r))
    return near_degenerate(r)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('cli')
    ap.add_argument('judge')
    ap.add_argument('--cases', type=int, default=200)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--keep')
    ap.add_argument('--threads', type=int, default=0)
    a = ap.parse_args()
    r = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix='random_agree.')
    bad = unread = pairs = 0
    try:
        files = []
        for i in range(a.cases):
            f = os.path.join(tmp, 'case%05d.stl' % i)
            write_binary(f, make(r))
            files.append(f)
        for f in files:
            res = agree.compare(a.cli, a.judge, f)
            rc = 0
            if res is None:
                unread += 1
            else:
                pairs += res[0]
                if res[1]:
                    print('%s: %s' % (f, '; '.join(res[1])))
                    rc = 1
            if a.threads > 1 and rc == 0:
                args = ['info', '--json', '--intersections', '--defects', '--shells', '--max-defects', '4000000000']
                one = subprocess.run([a.cli] + args + ['--threads', '1', f], capture_output=True)
                many = subprocess.run([a.cli] + args + ['--threads', str(a.threads), f], capture_output=True)
                if one.stdout != many.stdout or one.returncode != many.returncode:
                    print('%s: --threads %d differs from --threads 1' % (f, a.threads))
                    rc = 1
            if rc:
                bad += 1
                if a.keep:
                    os.makedirs(a.keep, exist_ok=True)
                    shutil.copy(f, a.keep)
    finally:
        shutil.rmtree(tmp)
    print('random_agree: %d random cases (seed %d, %d pairs; %d read by neither), %d differ' %
          (a.cases, a.seed, pairs, unread, bad))
    return 1 if bad or unread == a.cases else 0


if __name__ == '__main__':
    sys.exit(main())

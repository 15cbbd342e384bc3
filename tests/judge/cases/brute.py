#!/usr/bin/env python3
"""An independent check of the CGAL judge on the hand-built cases: the definitions of issue 21
in plain Python over exact rationals (fractions.Fraction), with a separating-axis test instead
of CGAL's predicates. Reads binary or ASCII STL, welds by exact equality, and prints the
judge's output format (without "seconds"). Slow: for small meshes only (a few thousand triangles).
usage: brute.py FILE.stl [--counts]"""
import struct
import sys
from fractions import Fraction


def f32(x):
    """The float32 value of x, exactly (a decimal goes through float64 first: fine for the cases,
    whose decimals are exact, and for all but rare ties elsewhere)."""
    return Fraction(struct.unpack('<f', struct.pack('<f', float(x)))[0])


def corners(path):
    data = open(path, 'rb').read()
    if len(data) >= 84 and 84 + 50 * struct.unpack_from('<I', data, 80)[0] == len(data):
        for t in range(struct.unpack_from('<I', data, 80)[0]):
            v = struct.unpack_from('<12f', data, 84 + 50 * t)
            for k in range(3):
                yield tuple(Fraction(c) for c in v[3 + 3 * k:6 + 3 * k])
        return
    for line in data.decode('latin-1').splitlines():
        w = line.split()
        if w and w[0] == 'vertex':
            yield tuple(f32(x) for x in w[1:4])


def read_stl(path):
    """Binary or ASCII STL, welded by exact equality (-0 == +0, as stltopo does)."""
    pts, ids, tris, cur = [], {}, [], []
    for p in corners(path):
        if p not in ids:
            ids[p] = len(pts)
            pts.append(p)
        cur.append(ids[p])
        if len(cur) == 3:
            tris.append(tuple(cur))
            cur = []
    return pts, tris


sub = lambda a, b: (a[0] - b[0], a[1] - b[1], a[2] - b[2])
dot = lambda a, b: a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
cross = lambda a, b: (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
ZERO = (0, 0, 0)


def orient(a, b, c, d):
    v = dot(cross(sub(b, a), sub(c, a)), sub(d, a))
    return (v > 0) - (v < 0)


def edges(P):
    return [sub(P[j], P[i]) for i in range(len(P)) for j in range(i + 1, len(P))]


def normal(P):
    return cross(sub(P[1], P[0]), sub(P[2], P[0])) if len(P) == 3 else None


def axes(P, Q):
    eP, eQ = edges(P), edges(Q)
    ns = [n for n in (normal(P), normal(Q)) if n is not None]
    ax = list(ns) + [cross(e, f) for e in eP for f in eQ] + [cross(n, e) for n in ns for e in eP + eQ]
    return [a for a in ax if a != ZERO]


def separated(P, Q, ax, strict):
    """True when some axis separates: strictly (closed sets disjoint) or weakly (interiors)."""
    for a in ax:
        p = [dot(a, x) for x in P]
        q = [dot(a, x) for x in Q]
        if strict and (max(p) < min(q) or max(q) < min(p)):
            return True
        if not strict and (max(p) <= min(q) or max(q) <= min(p)):
            return True
    return False


def meet(P, Q):  # closed convex hulls of 2 or 3 points share a point
    return not separated(P, Q, axes(P, Q), True)


def judge(pts, tris):
    n = len(tris)
    P = lambda t: [pts[v] for v in tris[t]]
    cand, zero, first, groups = [False] * n, [], {}, {}
    for t, (a, b, c) in enumerate(tris):
        if a == b or b == c or a == c:
            continue
        if cross(sub(pts[b], pts[a]), sub(pts[c], pts[a])) == ZERO:
            zero.append(t)
        else:
            cand[t] = True
        groups.setdefault(tuple(sorted(tris[t])), []).append(t)
    dup = [g for g in groups.values() if len(g) > 1]
    dup.sort()
    gid = {t: k for k, g in enumerate(dup) for t in g}

    def intersect(i, j):
        A, B = tris[i], tris[j]
        shared = [(x, y) for x in range(3) for y in range(3) if A[x] == B[y]]
        if len(shared) == 0:
            return meet(P(i), P(j))
        if len(shared) == 1:
            x, y = shared[0]
            sa = [pts[A[(x + 1) % 3]], pts[A[(x + 2) % 3]]]
            sb = [pts[B[(y + 1) % 3]], pts[B[(y + 2) % 3]]]
            return meet(sb, P(i)) or meet(sa, P(j))
        xa = [x for x in range(3) if x not in (s[0] for s in shared)][0]
        yb = [y for y in range(3) if y not in (s[1] for s in shared)][0]
        a, b = pts[A[shared[0][0]]], pts[A[shared[1][0]]]
        c, d = pts[A[xa]], pts[B[yb]]
        if orient(a, b, c, d) != 0:
            return False
        return dot(cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(d, a))) > 0

    def kind(i, j):
        A, B = P(i), P(j)
        oa = [orient(B[0], B[1], B[2], p) for p in A]
        ob = [orient(A[0], A[1], A[2], p) for p in B]
        if not any(oa):
            n = normal(A)
            ax = [a for a in (cross(n, e) for e in edges(A) + edges(B)) if a != ZERO]
            return 'touching' if separated(A, B, ax, False) else 'coplanar'
        both = lambda o: 1 in o and -1 in o
        return 'crossing' if both(oa) and both(ob) else 'touching'

    lo = [tuple(min(p[k] for p in P(t)) for k in range(3)) for t in range(n)]
    hi = [tuple(max(p[k] for p in P(t)) for k in range(3)) for t in range(n)]
    order = sorted((t for t in range(n) if cand[t]), key=lambda t: lo[t][0])
    pairs = []
    for k, i in enumerate(order):
        for j in order[k + 1:]:
            if lo[j][0] > hi[i][0]:
                break
            if any(lo[i][d] > hi[j][d] or lo[j][d] > hi[i][d] for d in range(3)):
                continue
            a, b = min(i, j), max(i, j)
            if a in gid and gid.get(b) == gid[a]:
                continue
            if intersect(a, b):
                pairs.append((a, b))
    pairs.sort()
    return zero, dup, [(a, b, kind(a, b)) for a, b in pairs]


if __name__ == '__main__':
    pts, tris = read_stl(sys.argv[1])
    zero, dup, pairs = judge(pts, tris)
    kinds = {k: sum(1 for p in pairs if p[2] == k) for k in ('crossing', 'touching', 'coplanar')}
    if '--counts' in sys.argv:
        print(len(tris), len(zero), len(dup), len(pairs), kinds['crossing'], kinds['touching'], kinds['coplanar'])
        sys.exit(0)
    print('{"triangles":%d,"zeroArea":[%s],"duplicateGroups":[%s],"pairs":%d,'
          '"kinds":{"crossing":%d,"touching":%d,"coplanar":%d}}' % (
              len(tris), ','.join(map(str, zero)), ','.join('[%s]' % ','.join(map(str, g)) for g in dup),
              len(pairs), kinds['crossing'], kinds['touching'], kinds['coplanar']))
    for a, b, k in pairs:
        print(a, b, k)

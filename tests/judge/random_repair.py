#!/usr/bin/env python3
"""`stltopo repair` (the default steps) on random damaged scenes, its result checked against
answers computed here and by the CGAL judge.

The scenes are random_nesting.py's (boxes, tetrahedra, voxel shapes and bipyramids on a small
integer grid, some inside out, nested, apart or sharing a corner, moved by 2^18-2^20 or shrunk by
2^-10-2^-20), kept only when the undamaged file is clean: no intersecting pair, zero-area or
duplicate triangle (by the judge), one closed manifold shell per shape (by stltopo). Each shape
then gets up to two kinds of damage, each of which a default step undoes without moving anything:

- copies of a triangle, same way round (duplicates removes them);
- degenerate triangles: one or two with a repeated corner, on a side of the shape or one corner
  three times (zero-area removes them);
- a flat sliver: a triangle (a, b, c) cut at a grid point m inside its side ab into (a, m, c)
  and (m, b, c), and the zero-area triangle (a, b, m) closing the gap (zero-area flips ab);
- a chain of two slivers: (a, b, c) cut at m1 and m2 inside ab, closed by (a, b, m2) and
  (a, m2, m1), whose longest side has the first sliver across it (zero-area flips them in
  rounds);
- a T-junction: the same cut without the sliver (stitch splits the neighbour's side at m);
- triangles flipped, fewer than half of the shape's (orient);
- holes: one or two triangles, or a box face's two, removed, sharing no corner (fill-holes
  puts the same surface back; a shape with holes is not flipped, as orient turns only closed
  shells and leaves an open one as it runs);
- walls: one or two triangles, sharing no corner, each with a reversed copy (a zero-thickness
  wall: the repair runs with --remove-walls, duplicates takes both, and the hole is filled as
  above);
- a crack: a face of two coplanar triangles cut off and moved by 0.25 on each axis, its
  triangles last in the file (the repair runs with --stitch-tolerance of half a grid unit;
  stitch zips the crack, keeping the lower ids: the shape's own corners; not beside flipped
  triangles, as stitch runs before orient and refuses to zip a crack into an inconsistent edge).

The answer for the result, from docs/REPAIR.md: no degenerate triangle, no zero-area or duplicate
triangle and no intersecting pair (the judge), watertight, manifold unless two shapes share a corner, one shell
per shape with the shape's volume exactly (its triangles' signed volumes added up in rationals,
in the orientation expected); a shape that had holes keeps the way it was built (orient runs
before fill-holes and turns only closed shells); any other shape faces outward at even depth
and inward at odd depth, counting the shapes around it that were closed when orient ran;
`solid` and the exit status follow. The change log's `afterReport` must be what `stltopo info
--json` says of the file written, no step may skip an item (but stitch with a crack's
tolerance, which also tries, and may refuse, a corner within it of a hole's own side), and the
run on 2 threads must print and write the same bytes as on one.

  random_repair.py STLTOPO_CLI JUDGE [--cases N] [--seed S] [--keep DIR]
"""
import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
from fractions import Fraction

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from random_agree import write_binary  # noqa: E402
from random_nesting import arguments, clean, move, orient, report, scene  # noqa: E402


def read_binary(path):
    with open(path, 'rb') as f:
        data = f.read()
    n = struct.unpack_from('<I', data, 80)[0]
    tris = []
    for i in range(n):
        v = struct.unpack_from('<12f', data, 84 + 50 * i)
        tris.append((v[3:6], v[6:9], v[9:12]))
    return tris


def volume6(tris):
    """Six times the signed volume, exactly (float32 coordinates are exact rationals)."""
    s = Fraction(0)
    for a, b, c in tris:
        a, b, c = ([Fraction(x) for x in p] for p in (a, b, c))
        s += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
              + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return s


def edges(t):
    return [frozenset((t[i], t[(i + 1) % 3])) for i in range(3)]


def components(tris):
    """Edge-connected components of a triangle list (positions taken as they are)."""
    parent = list(range(len(tris)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    seen = {}
    for i, t in enumerate(tris):
        for e in edges(t):
            if e in seen:
                parent[find(i)] = find(seen[e])
            else:
                seen[e] = i
    groups = {}
    for i in range(len(tris)):
        groups.setdefault(find(i), []).append(i)
    return sorted(groups.values())


def cut_points(r, a, b, count):
    """count grid points strictly inside the segment ab, in order from a, or None."""
    d = [b[k] - a[k] for k in range(3)]
    g = math.gcd(math.gcd(abs(d[0]), abs(d[1])), abs(d[2]))
    if g <= count:
        return None
    return [tuple(a[i] + d[i] // g * k for i in range(3)) for k in sorted(r.sample(range(1, g), count))]


def damage(r, tris):
    """Damages one shape (its triangles as the file has them). Returns the new list, whether it
    has holes, the kinds done, and the triangles of a face cut off and moved (a crack: they go
    last in the file, so that their corners have the highest ids and stitch keeps the others)."""
    tris = list(tris)
    n = len(tris)
    used = set()  # triangles a damage has touched
    removed = set()
    added = []
    detached = []
    kinds = []
    holed = False
    for kind in r.sample(['copies', 'sliver', 'chain', 'tjunction', 'flips', 'holes', 'walls', 'crack',
                          'degenerate'], r.randint(1, 2)):
        free = [i for i in range(n) if i not in used]
        if kind == 'copies':
            for i in r.sample(free, min(len(free), r.randint(1, 2))):
                used.add(i)
                added += [tris[i]] * r.randint(1, 2)
        elif kind == 'degenerate':  # on a side of the shape, or one corner three times
            for _ in range(r.randint(1, 2)):
                p, q = r.sample(tris[r.randrange(n)], 2)
                added.append(r.choice([(p, p, q), (p, q, q), (q, p, q), (p, p, p)]))
        elif kind in ('sliver', 'tjunction', 'chain'):
            r.shuffle(free)
            for i in free:
                side = r.randrange(3)
                a, b, c = tris[i][side], tris[i][(side + 1) % 3], tris[i][(side + 2) % 3]
                ms = cut_points(r, a, b, 2 if kind == 'chain' else 1)
                j = next((j for j in free if j != i and
                          any(tris[j][s] == b and tris[j][(s + 1) % 3] == a for s in range(3))), None)
                if ms is None or j is None:
                    continue
                used.update((i, j))
                tris[i] = (a, ms[0], c)
                added += [(p, q, c) for p, q in zip(ms, ms[1:] + [b])]
                if kind == 'sliver':
                    added.append((a, b, ms[0]))
                elif kind == 'chain':  # two slivers, the second only beside the first
                    added += [(a, b, ms[1]), (a, ms[1], ms[0])]
                break
            else:
                continue
        elif kind == 'flips':
            if holed or 'crack' in kinds:
                continue
            for i in r.sample(free, min(len(free), r.randint(1, max(1, (n - 1) // 2)))):
                used.add(i)
                tris[i] = (tris[i][0], tris[i][2], tris[i][1])
        else:  # holes, walls (a reversed copy: --remove-walls takes both), or a crack
            if 'flips' in kinds:  # (a crack beside a flipped triangle would zip into an
                continue          # inconsistent edge: stitch runs before orient, and refuses)
            corners = set()
            for t in (tris[i] for i in used):
                corners.update(t)
            picks = []
            # a face of two coplanar triangles (a box's, or a voxel shape's), or single triangles
            if kind == 'crack' or (kind == 'holes' and r.random() < 0.4):
                for i in range(0, n - 1, 2):
                    if i in free and i + 1 in free and len(set(tris[i]) | set(tris[i + 1])) == 4 \
                            and orient(*tris[i], [q for q in tris[i + 1] if q not in tris[i]][0]) == 0:
                        picks.append([i, i + 1])
            else:
                picks = [[i] for i in free]
            r.shuffle(picks)
            took, target = 0, 1 if kind == 'crack' else r.randint(1, 2)
            for p in picks:
                pts = {q for i in p for q in tris[i]}
                if pts & corners:
                    continue
                corners |= pts
                if kind == 'holes':
                    removed.update(p)
                elif kind == 'crack':  # the face, moved 0.25 a coordinate: 0.433 from where it was
                    d = tuple(r.choice([-0.25, 0.25]) for _ in range(3))
                    removed.update(p)
                    detached += [tuple(tuple(c + e for c, e in zip(q, d)) for q in tris[i]) for i in p]
                else:
                    added += [(tris[i][0], tris[i][2], tris[i][1]) for i in p]
                used.update(p)
                took += 1
                if took == target:
                    break
            if not took:
                continue
            holed |= kind != 'crack'
        kinds.append(kind)
    out = [t for i, t in enumerate(tris) if i not in removed] + added
    return out, holed, kinds, detached


def main():
    a = arguments(__doc__)
    r = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix='random_repair.')
    bad = compared = solids = 0
    done = {}
    try:
        for i in range(a.cases):
            shapes = scene(r)
            built = [[(t[0], t[2], t[1]) for t in s] if inward else list(s) for s, inward, _, _ in shapes]
            f = os.path.join(tmp, 'scene%05d.stl' % i)
            write_binary(f, [t for s in built for t in s])
            if clean(a.cli, a.judge, f, shapes) is None:
                continue

            # the answer
            n = len(shapes)
            verts = [sorted({p for t in s[0] for p in t}) for s in shapes]
            inside = [[j != k and all(shapes[j][3](p) for p in verts[k]) for j in range(n)] for k in range(n)]
            shared = len({p for v in verts for p in v}) != sum(len(v) for v in verts)
            damaged, holed, walls, detached = [], [], False, []
            for s in built:
                d, h, kinds, cut = damage(r, s)
                damaged.append(d)
                holed.append(h)
                detached += cut
                walls |= 'walls' in kinds
                for k in kinds:
                    done[k] = done.get(k, 0) + 1
            want = []
            for k in range(n):
                if holed[k]:
                    want.append(shapes[k][1])  # inward as built
                else:
                    want.append(sum(inside[k][j] and not holed[j] for j in range(n)) % 2 == 1)
            solid = not shared and all(want[k] == (sum(inside[k]) % 2 == 1) for k in range(n))
            size = [abs(volume6(s)) for s in built]

            flat = [t for s in damaged for t in s]
            rest = len(flat)
            flat += detached
            tris = move(r, flat)
            order = list(range(rest))
            r.shuffle(order)
            write_binary(f, [tris[k] for k in order + list(range(rest, len(tris)))])
            out1, out2 = f + '.1.stl', f + '.2.stl'
            opts = ['--remove-walls'] if walls else []
            if detached:  # a tolerance of half a grid unit, scaled as move() scaled the scene
                g0, m0 = flat[0][0], tris[0][0]
                g1, m1 = next((p, q) for t, u in zip(flat, tris) for p, q in zip(t, u) if p[0] != g0[0])
                opts += ['--stitch-tolerance', repr(0.5 * (m1[0] - m0[0]) / (g1[0] - g0[0]))]
            run1 = subprocess.run([a.cli, 'repair', f, out1, '--threads', '1'] + opts, capture_output=True, text=True)
            run2 = subprocess.run([a.cli, 'repair', f, out2, '--threads', '2'] + opts, capture_output=True, text=True)
            compared += 1
            solids += solid
            problems = []
            if run1.returncode not in (0, 3) or not os.path.exists(out1):
                problems.append('repair failed (%d): %s' % (run1.returncode, run1.stderr.strip()))
            else:
                log = json.loads(run1.stdout)
                if run2.stdout.replace(out2, out1) != run1.stdout or run2.returncode != run1.returncode \
                        or open(out1, 'rb').read() != open(out2, 'rb').read():
                    problems.append('--threads 2 differs from --threads 1')
                for st in log['steps']:
                    # with a tolerance, stitch also tries (and may refuse) a corner within it of
                    # a hole's own side: the result's checks below still hold it to account
                    if st['status'] != 'ok' or (st['skipped'] and not (detached and st['step'] == 'stitch')):
                        problems.append('step %s: status %s, %d skipped' % (st['step'], st['status'], st['skipped']))
                info = json.loads(subprocess.run([a.cli, 'info', '--json', out1], capture_output=True,
                                                 text=True, check=True).stdout)
                after = dict(log['afterReport'])
                for key in set(info) | set(after):
                    if key != 'file' and info.get(key) != after.get(key):
                        problems.append('afterReport %s %r, the file written %r' % (key, after.get(key), info.get(key)))
                j = subprocess.run([a.judge, '--count-only', out1], capture_output=True, text=True, check=True)
                head = json.loads(j.stdout.splitlines()[0])
                if head['pairs'] or head['zeroArea'] or head['duplicateGroups']:
                    problems.append('the judge finds %d pairs, zero-area %r, duplicates %r in the result' %
                                    (head['pairs'], head['zeroArea'], head['duplicateGroups']))
                fig = log['after']
                if fig['degenerateTriangles']:
                    problems.append('%d degenerate triangles in the result' % fig['degenerateTriangles'])
                if not fig['watertight'] or fig['manifold'] == shared:  # shapes sharing a corner pinch it
                    problems.append('watertight %r, manifold %r (shapes share a corner: %r)' % (
                        fig['watertight'], fig['manifold'], shared))
                if fig['solid'] != solid:
                    problems.append('solid %r, expected %r' % (fig['solid'], solid))
                rc = 0 if fig['watertight'] and fig['manifold'] and fig['solid'] else 3
                if run1.returncode != rc:
                    problems.append('exit status %d, expected %d' % (run1.returncode, rc))
                # each shell of the result against its shape: volume and orientation
                res = read_binary(out1)
                owner = {}
                for k, v in enumerate(verts):
                    for p in v:
                        owner.setdefault(p, set()).add(k)
                # the result's positions back in the scene's grid (move() is one to one)
                src = {p1: p0 for t0, t1 in zip(flat, tris) for p0, p1 in zip(t0, t1)}
                grid = {p for s in built for t in s for p in t}
                comps = components(res)
                if len(comps) != n:
                    problems.append('%d shells in the result, %d shapes' % (len(comps), n))
                else:
                    hit = set()
                    for c in comps:
                        pts = {src.get(tuple(p)) for q in c for p in res[q]}
                        ks = set.intersection(*[owner.get(p, set()) for p in pts if p in grid] or [set()])
                        if len(ks) != 1:
                            problems.append('a shell of the result matches shapes %r' % sorted(ks))
                            continue
                        k = ks.pop()
                        hit.add(k)
                        v = volume6([tuple(src[tuple(p)] for p in res[q]) for q in c])
                        if abs(v) != size[k]:
                            problems.append('shape %d: volume*6 %s, built %s' % (k, abs(v), size[k]))
                        if (v < 0) != want[k]:
                            problems.append('shape %d faces %s, expected %s (holes %r, depth %d)' % (
                                k, 'inward' if v < 0 else 'outward', 'inward' if want[k] else 'outward',
                                holed[k], sum(inside[k])))
                    if len(hit) != n and not problems:
                        problems.append('shapes %r have no shell' % sorted(set(range(n)) - hit))
            bad += report(f, problems, a.keep)
    finally:
        shutil.rmtree(tmp)
    print('random_repair: %d scenes (seed %d), %d repaired (%d solid expected; damage: %s), %d differ' % (
        a.cases, a.seed, compared, solids, ', '.join('%s %d' % kv for kv in sorted(done.items())), bad))
    return 1 if bad or compared == 0 else 0


if __name__ == '__main__':
    sys.exit(main())

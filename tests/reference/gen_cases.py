#!/usr/bin/env python3
"""Generated STL cases with the results that the reader and topology specifications state for them.

  gen_cases.py DIR        writes every case to DIR/<name>.stl (for check-reference.sh)
  gen_cases.py --check    runs the Python reference on every case and checks the
                          expectations below (a self-test of the reference)

Every expectation here comes from the specification texts or from reasoning about the
construction, never from a program's output.
"""

import os
import struct
import sys
from decimal import Decimal, getcontext

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stl_reference as ref  # noqa: E402


# ---------------------------------------------------------------------------
# writers

def binary(tris, header=b'generated', attrs=None, normals=None, count=None, extra=b''):
    h = header.ljust(80, b'\0')[:80]
    out = [h, struct.pack('<I', len(tris) if count is None else count)]
    for i, t in enumerate(tris):
        n = normals[i] if normals else (0.0, 0.0, 0.0)
        a = attrs[i] if attrs else 0
        out.append(struct.pack('<12fH', *n, *t[0], *t[1], *t[2], a))
    return b''.join(out) + extra


def fmt(x):
    if isinstance(x, str):
        return x
    return repr(float(x))


def ascii_stl(solids, eol='\n', endsolid=True):
    """solids: [(name, [tri...])], tri = ((x,y,z),(x,y,z),(x,y,z)) or a list of corners."""
    lines = []
    for k, (name, tris) in enumerate(solids):
        lines.append(('solid ' + name).rstrip())
        for t in tris:
            lines.append('  facet normal 0 0 0')
            lines.append('    outer loop')
            for p in t:
                lines.append('      vertex %s %s %s' % tuple(fmt(c) for c in p))
            lines.append('    endloop')
            lines.append('  endfacet')
        if endsolid or k < len(solids) - 1:
            lines.append('endsolid ' + name)
    return (eol.join(lines) + eol).encode('utf-8')


# ---------------------------------------------------------------------------
# shapes

CUBE_V = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]


def _quad(a, b, c, d):
    return [(a, b, c), (a, c, d)]


def cube_faces():
    """12 outward triangles of the unit cube as vertex-index triples into CUBE_V.
    Index = 4x + 2y + z."""
    f = []
    f += _quad(0, 1, 3, 2)  # x=0 (normal -x): 000,001,011,010
    f += _quad(4, 6, 7, 5)  # x=1
    f += _quad(0, 4, 5, 1)  # y=0
    f += _quad(2, 3, 7, 6)  # y=1
    f += _quad(0, 2, 6, 4)  # z=0
    f += _quad(1, 5, 7, 3)  # z=1 (top): last two triangles
    return f


def cube(offset=(0, 0, 0), size=1.0):
    return [tuple(tuple(offset[k] + size * CUBE_V[i][k] for k in range(3)) for i in f)
            for f in cube_faces()]


def grid(n, m, wrap_u=False, wrap_v=False, removed=(), embed=None):
    """Triangulated n x m quad grid; quads in `removed` are left out."""
    nu = n if wrap_u else n + 1
    nv = m if wrap_v else m + 1

    def vid(i, j):
        return (i % nu if wrap_u else i), (j % nv if wrap_v else j)

    tris = []
    for i in range(n):
        for j in range(m):
            if (i, j) in removed:
                continue
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            for t in ((a, b, c), (a, c, d)):
                tris.append(tuple(embed(*p) if embed else (p[0], p[1], 0) for p in t))
    return tris


def torus(n=12, m=8, removed=()):
    import math

    def embed(i, j):
        u = 2 * math.pi * i / n
        v = 2 * math.pi * j / m
        r = 3 + math.cos(v)
        # round through float32 so that the binary and ASCII writers agree exactly
        return tuple(struct.unpack('<f', struct.pack('<f', c))[0]
                     for c in (r * math.cos(u), r * math.sin(u), math.sin(v)))
    return grid(n, m, True, True, removed, embed)


def double_rounding_text():
    """A decimal just above the float32 midpoint 1 + 2^-24: rounding through double lands
    exactly on the midpoint (and then ties to 1.0); strtof gives 1 + 2^-23."""
    getcontext().prec = 80
    x = Decimal(1) + Decimal(2) ** -24 + Decimal(2) ** -60
    return format(x, 'f')


# ---------------------------------------------------------------------------

def cases():
    C = []

    def add(name, data, **expect):
        C.append((name, data, expect))

    cb = cube()
    add('cube', binary(cb), vertices=8, edges=18, eulerCharacteristic=2, genus=0,
        watertight=True, manifold=True, holes=0, seams=0, shells=1)
    add('cube_ascii', ascii_stl([('cube', cb)]), format='ascii', vertices=8, edges=18, genus=0)
    add('cube_open_top', binary(cb[:10]), boundaryEdges=4, holes=1, holeSizes=[4], seams=0,
        watertight=False, genus=None, manifold=True)
    import random
    rnd = random.Random(4)
    sh = cb[:]
    rnd.shuffle(sh)
    add('cube_shuffled', binary(sh), vertices=8, edges=18, eulerCharacteristic=2, genus=0,
        watertight=True)
    flipped = cb[:]
    flipped[3] = (flipped[3][0], flipped[3][2], flipped[3][1])
    add('cube_flipped_face', binary(flipped), inconsistentEdges=3, holes=0, watertight=False,
        boundaryEdges=0, orientations=['inconsistent'], closed=[False],
        defectCounts={'inconsistentEdges': 3, 'seams': 2, 'holes': 0})
    add('cube_plus_degenerate', binary(cb + [((0, 0, 0), (0, 0, 0), (1, 1, 1))]),
        degenerateTriangles=1, edges=18, watertight=True, genus=0, triangles=13)
    # two cubes sharing the edge x=1,y=1 (z in [0,1])
    add('two_cubes_shared_edge', binary(cb + cube((1, 1, 0))), nonManifoldEdges=1,
        holes=0, seams=0, boundaryEdges=0, watertight=False, manifold=False, shells=1,
        orientations=['outward'], closed=[False], shellManifold=[False],
        defectCounts={'nonManifoldEdges': 1, 'nonManifoldVertices': 2})
    # two cubes touching at the corner (1,1,1)
    add('two_cubes_shared_corner', binary(cb + cube((1, 1, 1))), nonManifoldVertices=1,
        nonManifoldEdges=0, watertight=True, manifold=False, shells=2, eulerCharacteristic=3, genus=None,
        closed=[True, True], shellManifold=[True, True], orientations=['outward', 'outward'])
    add('torus', binary(torus()), eulerCharacteristic=0, genus=1, watertight=True, manifold=True)
    add('torus_two_holes', binary(torus(removed=((0, 0), (6, 4)))), holes=2, holeSizes=[4, 4],
        boundaryEdges=8, genus=None)
    # 4x4 quad grid with quads (1,1) and (2,2) removed: the two holes touch at vertex (2,2)
    g = grid(4, 4, removed=((1, 1), (2, 2)))
    add('two_holes_touching', binary(g), holes=2, holeSizes=[16, 8], nonManifoldVertices=1,
        boundaryEdges=24, manifold=False)
    # soup of separate triangles
    add('soup3', binary([((i, 0, 0), (i + 0.5, 1, 0), (i, 0, 1)) for i in range(0, 9, 3)]),
        holes=3, holeSizes=[3, 3, 3], shells=3, boundaryEdges=9, orientations=['open'] * 3,
        shellManifold=[True] * 3)

    # shells and defects (issue 16); expectations on the shell list and defect lists:
    #   orientations/closed/shellManifold/shellSolids: per shell, in shell order
    #   defectCounts: {kind: count}; degenerateCorners: the items' corners
    add('two_cubes_one_inside_out', binary(cb + [(t[0], t[2], t[1]) for t in cube((3, 0, 0), 2)]),
        shells=2, orientations=['outward', 'inward'], closed=[True, True], shellManifold=[True, True])
    add('bowtie', binary([((0, 0, 0), (1, -1, 0), (1, 1, 0)), ((0, 0, 0), (-1, 1, 0), (-1, -1, 0))]),
        shells=2, orientations=['open', 'open'], shellManifold=[True, True], manifold=False,
        defectCounts={'nonManifoldVertices': 1, 'holes': 2})
    add('pillow_flat', binary([((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((0, 0, 0), (0, 1, 0), (1, 0, 0))]),
        orientations=['flat'], closed=[True])
    add('degenerate_corners', binary(cb + [((0, 0, 0), (0, 0, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (1, 0, 0)),
                                           ((1, 0, 0), (0, 0, 0), (1, 0, 0)), ((2, 2, 2), (2, 2, 2), (2, 2, 2))]),
        degenerateTriangles=4, degenerateCorners=[[0, 1], [1, 2], [0, 2], [0, 1, 2]], orientations=['outward'])
    add('shell_across_solids', ascii_stl([('a', cb[:6]), ('b', cb[6:]), ('c', cube((3, 0, 0)))]),
        shells=2, shellSolids=['mixed', 2], orientations=['outward', 'outward'])

    # reading
    add('minus_zero', binary([((0.0, 0, 0), (1, 0, 0), (0, 1, 0)),
                              ((-0.0, -0.0, -0.0), (0, 1, 0), (1, 0, 0))]),
        vertices=3, triangles=2, inconsistentEdges=0, boundaryEdges=0, edges=3)
    add('binary_header_solid', binary(cb, header=b'solid looks like ascii'), format='binary',
        solids=[('solid looks like ascii', 12)])
    add('trailing_bytes', binary(cb, extra=b'\n\n\n'), format='binary', warnings=['trailing-bytes'])
    add('concatenated', binary(cb, header=b'part one') + binary(cube((3, 0, 0)), header=b'  part two  '),
        format='binary', triangles=24, solids=[('part one', 12), ('part two', 12)], shells=2)
    add('truncated', binary(cb)[:-10], error='truncated')
    add('truncated_count', binary(cb, count=13), error='truncated')
    add('empty', b'', error='empty')
    add('not_stl', b'hello world\n', error='not-stl')
    add('magics', binary(cb, header=b'COLOR=\x80\x80\x80\xff', attrs=[(19 << 10) | (19 << 5) | 19] * 12),
        colors='magics')
    add('viscam', binary(cb, attrs=[0x8000 | (31 << 10)] * 12), colors='viscam')
    add('attribute_without_bit15', binary(cb, attrs=[0x2020] * 12), colors='none')
    add('normal_mismatch', binary(cb[:2], normals=[(1, 0, 0), (-1, 0, 0)]), normalMismatches=1)
    # Stored normals exactly perpendicular to the winding's normal (n = b - a), which the dot
    # product in double puts below 0 (-416, -256, -128): not mismatches, as the exact sign is 0.
    # The last triangle's normal does point against its winding.
    ties = [((-130702, -1375272, 2076856), (-353024, -904813, -1557148), (-1782875, 2002082, -470987)),
            ((-853895, 1730260, 1636927), (299080, 895037, 1477401), (-964894, -769238, -1278286)),
            ((-252036, 790227, -51286), (-1997192, 383415, 782080), (-253409, 141283, -1814846)),
            ((0, 0, 0), (1, 0, 0), (0, 1, 0))]
    add('normal_perpendicular', binary(ties, normals=[tuple(b[k] - a[k] for k in range(3)) for a, b, c in ties[:3]]
                                       + [(0, 0, -1)]), normalMismatches=1)
    add('nan', binary([((0, 0, 0), (float('nan'), 0, 0), (0, 1, 0))]), error='non-finite')
    add('ascii_missing_endsolid', ascii_stl([('x', cb)], endsolid=False), warnings=['missing-endsolid'],
        triangles=12)
    add('ascii_crlf_upper', ascii_stl([('X', cb)], eol='\r\n').upper(), triangles=12, vertices=8)
    add('ascii_cr_only', ascii_stl([('x', cb)], eol='\r'), triangles=12, vertices=8)
    add('ascii_bom', b'\xef\xbb\xbf  ' + ascii_stl([('bom', cb)]), format='ascii', triangles=12)
    add('ascii_two_solids_utf8', ascii_stl([('月球', cb), ('', cube((2, 0, 0)))]),
        solids=[('月球', 12), ('', 12)], shells=2)
    add('ascii_empty_solid', b'solid empty\nendsolid empty\n', triangles=0, vertices=0,
        watertight=False, genus=None, bbox=None)
    add('ascii_unexpected_end', ascii_stl([('x', cb)])[:-60], error='unexpected-end')
    four = ascii_stl([('x', [((0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0))])])
    add('ascii_four_vertices', four, error='ascii-syntax')
    add('ascii_bad_number', ascii_stl([('x', [((0, 0, 0), ('1.0.0', 0, 0), (0, 1, 0))])]),
        error='ascii-syntax')
    add('ascii_inf', ascii_stl([('x', [((0, 0, 0), ('inf', 0, 0), (0, 1, 0))])]), error='non-finite')
    add('ascii_number_forms', ascii_stl([('x', [(('0x1p-1', '+.5', '5e-1'), ('1.', '0', '0'),
                                                 ('0', '1E0', '-0'))])]),
        vertices=3, triangles=1)
    dr = double_rounding_text()
    add('ascii_double_rounding', ascii_stl([('x', [((dr, 0, 0), (0, 1, 0), (0, 0, 1))])]),
        bbox={'min': [0.0, 0.0, 0.0], 'max': [1.0 + 2.0 ** -23, 1.0, 1.0]})
    add('ascii_denormal', ascii_stl([('x', [(('1e-45', 0, 0), (0, 1, 0), (0, 0, 1))])]),
        bbox={'min': [0.0, 0.0, 0.0], 'max': [struct.unpack('<f', struct.pack('<I', 1))[0], 1.0, 1.0]})

    # topology corner cases
    fin = ((0, 0, 0), (1, 0, 0), (0.5, -1, 0.5))  # a fin on the cube's edge (0,0,0)-(1,0,0)
    add('cube_with_fin', binary(cb + [fin]), nonManifoldEdges=1, boundaryEdges=2, seams=1,
        holes=0, watertight=False, orientations=['open'], shellManifold=[False],
        defectCounts={'nonManifoldEdges': 1, 'seams': 1})
    add('cube_with_two_fins', binary(cb + [fin, ((1, 0, 0), (0, 0, 0), (0.5, -1, -0.5))]),
        nonManifoldEdges=1, watertight=False)
    add('cube_twice', binary(cb + cb), nonManifoldEdges=18, holes=0, seams=0, shells=1)
    add('flipped_cube_after_cube', binary(cb + [(t[0], t[2], t[1]) for t in cb]),
        nonManifoldEdges=18)

    # reading corner cases (policies the specification leaves partly open)
    txt = ascii_stl([('x', cb[:2])]).decode()
    add('ascii_tokens_across_lines', txt.replace('facet normal', 'facet\nnormal')
        .replace('outer loop', 'outer\n\tloop').encode(), triangles=2)
    add('ascii_extra_tokens_after_endfacet', txt.replace('endfacet', 'endfacet extra').encode())
    add('ascii_facet_without_normal', txt.replace('facet normal 0 0 0', 'facet').encode(),
        triangles=2)
    add('ascii_nan_normal', txt.replace('facet normal 0 0 0', 'facet normal nan nan nan').encode(),
        triangles=2)
    add('ascii_garbage_after_endsolid', txt.encode() + b'garbage\n')
    add('ascii_solid_without_endsolid_then_solid',
        txt.replace('endsolid x', '').encode() + ascii_stl([('y', cb[2:4])]))
    add('ascii_only_solid', b'solid\n', triangles=0)
    add('ascii_overflow', ascii_stl([('x', [((0, 0, 0), ('1e39', 0, 0), (0, 1, 0))])]),
        error='non-finite')
    add('ascii_long_name', ascii_stl([('n' * 5000, cb[:1])]), warnings=['name-truncated'])
    add('ascii_utf8_split_at_cap', ascii_stl([('n' * 4095 + '月', cb[:1])]),
        warnings=['name-truncated'], solids=[('n' * 4095, 1)])
    # stltopo.h: kMaxNameBytes = 4096, "longer solid names are cut (warning)"
    add('ascii_name_4096_bytes', ascii_stl([('n' * 4096, cb[:1])]), warnings=[],
        solids=[('n' * 4096, 1)])
    add('spaces_100', b' ' * 100)
    add('bom_only', b'\xef\xbb\xbf')
    add('binary_nan_normal', binary(cb[:1], normals=[(float('nan'), 0, 0)]), triangles=1)
    add('binary_inf_coordinate', binary([((0, 0, 0), (float('inf'), 0, 0), (0, 1, 0))] + cb),
        error='non-finite')
    add('binary_huge_count', binary(cb, count=(1 << 28) + 1))
    add('concatenated_trailing', binary(cb, header=b'a') + binary(cb[:2], header=b'b', extra=b'xy'),
        warnings=['trailing-bytes'], triangles=14)
    add('concatenated_bad_second', binary(cb, header=b'a') + binary(cb[:2], header=b'b', count=5))
    add('binary_header_solid_trailing', binary(cb, header=b'solid x', extra=b'\n'),
        format='binary', warnings=['trailing-bytes'])
    add('binary_header_solid_truncated', binary(cb, header=b'solid x')[:-7], error='truncated')
    add('ascii_then_binary_bytes', b'solid x\n' + bytes(range(256)) * 2, error='truncated')

    # more probes
    tri = ((0, 0, 0), (1, 0, 0), (0, 1, 0))
    add('pillow', binary([tri, (tri[0], tri[2], tri[1])]), vertices=3, edges=3, watertight=True,
        eulerCharacteristic=2, genus=0, holes=0)
    add('same_triangle_twice', binary([tri, tri]), inconsistentEdges=3, holes=0, seams=2)
    add('five_sides_on_one_edge', binary([((0, 0, 0), (1, 0, 0), (0.5, 1, k * 0.3)) if k % 2 == 0
                                          else ((1, 0, 0), (0, 0, 0), (0.5, 1, k * 0.3)) for k in range(5)]),
        nonManifoldEdges=1)
    mob = []
    n = 6
    for i in range(n):  # a Moebius band: the last quad joins with a half twist
        a, b = ('t', i), ('b', i)
        c, d = (('t', i + 1), ('b', i + 1)) if i < n - 1 else (('b', 0), ('t', 0))
        mob += [(a, b, d), (a, d, c)]
    pos = {}
    for i in range(n):
        pos[('t', i)] = (i, 0, 1)
        pos[('b', i)] = (i, 0, -1) if i else (i, 2, -1)
    add('moebius', binary([tuple(pos[v] for v in t) for t in mob]), inconsistentEdges=1)
    add('concatenated_second_header_solid', binary(cb, header=b'one') + binary(cb[:2], header=b'solid two'),
        solids=[('one', 12), ('solid two', 2)])
    forms = [('0X1P+2', 'infinity', '0'), ('1', '2', '3'), ('4', '5', '6')]
    add('ascii_infinity_word', ascii_stl([('x', [forms])]), error='non-finite')
    for bad in ('1e+', '.e1', '+-1', '1d5', '1,5', '0x', '1_0', '--1', 'nan(', '0x1p'):
        add('ascii_bad_%s' % bad.replace('.', 'dot').replace('+', 'plus').replace('-', 'minus')
            .replace(',', 'comma').replace('(', 'paren'),
            ascii_stl([('x', [((bad, 0, 0), (0, 1, 0), (0, 0, 1))])]), error='ascii-syntax')
    add('ascii_nan_payload', ascii_stl([('x', [(('-nan(123)', 0, 0), (0, 1, 0), (0, 0, 1))])]),
        error='non-finite')
    long_ok = '0.' + '0' * 4093 + '1'  # 4096 characters
    # stltopo.h: kMaxNumberChars = 4096, "longer ASCII numbers are an error"
    add('ascii_number_4096_chars', ascii_stl([('x', [((long_ok, 0, 0), (0, 1, 0), (0, 0, 1))])]),
        triangles=1)
    add('ascii_number_4097_chars', ascii_stl([('x', [(('0' + long_ok, 0, 0), (0, 1, 0), (0, 0, 1))])]),
        error='ascii-syntax')
    add('ascii_hex_double_rounding', ascii_stl([('x', [(('0x1.000001000000000000001p0', 0, 0), (0, 1, 0),
                                                        (0, 0, 1))])]),
        bbox={'min': [0.0, 0.0, 0.0], 'max': [1.0 + 2.0 ** -23, 1.0, 1.0]})
    add('ascii_minus_zero_degenerate', ascii_stl([('x', [((0, 0, 0), ('-0', '-0.0', '-0e5'), (1, 1, 1))])]),
        degenerateTriangles=1, vertices=2, edges=0)
    add('ascii_tabs_and_blank_lines', ascii_stl([('x', cb[:2])]).replace(b' ', b'\t').replace(b'\n', b'\n\n'),
        triangles=2)
    return C


def check():
    bad = 0
    for name, data, expect in cases():
        try:
            got = ref.info(name, data, self_check=True, shells=True, defects=1000)
        except ref.StlError as e:
            got = {'error': e.code}
        per_shell = {'orientations': 'orientation', 'closed': 'closed', 'shellManifold': 'manifold',
                     'shellSolids': 'solid'}
        for k, v in expect.items():
            if 'error' in got and k != 'error':
                g = ('error', got['error'])
            elif k in per_shell:
                g = [x[per_shell[k]] for x in got['shellList']]
            elif k == 'defectCounts':
                g = {kind: got['defects'][kind]['count'] for kind in v}
            elif k == 'degenerateCorners':
                g = [x['corners'] for x in got['defects']['degenerateTriangles']['items']]
            elif k == 'error':
                g = got.get('error')
            elif 'error' in got:
                g = ('error', got['error'])
            elif k == 'warnings':
                g = sorted(w['code'] for w in got['warnings'])
            elif k == 'solids':
                g = [(s['name'], s['triangles']) for s in got['solids']]
            else:
                g = got.get(k)
            if g != v:
                print('%s: %s expected %r, got %r' % (name, k, v, g))
                bad += 1
    print('generated cases: %d expectation(s) failed' % bad)
    return 1 if bad else 0


def main(argv):
    if argv == ['--check']:
        return check()
    if len(argv) != 1:
        sys.stderr.write(__doc__)
        return 2
    os.makedirs(argv[0], exist_ok=True)
    for name, data, _ in cases():
        with open(os.path.join(argv[0], name + '.stl'), 'wb') as f:
            f.write(data)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

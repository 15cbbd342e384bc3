#!/usr/bin/env python3
"""Comparison harness for scripts/check-reference.sh.

  compare.py cli CLI.jsonl REF.jsonl
      Field-by-field comparison of `stltopo info --json` output with the Python
      reference (tests/reference/stl_reference.py). Integers, strings and booleans
      must be equal, floats within a relative tolerance of 1e-6, warnings are
      compared by their code lists, errors by their codes. Prints one block per
      differing file; exit status 1 on any mismatch.

  compare.py cli CLI.jsonl REF.jsonl RC.tsv
      The same, and also checks the CLI's exit status per file (RC.tsv: lines
      "status<TAB>file"): 0 when the file was read, 1 when it failed.

  compare.py same A.jsonl B.jsonl
      Checks that two runs of the CLI printed identical objects, file for file in
      order, ignoring the "file" field (multi-file run vs one run per file, or
      stdin "-" vs a path: streaming must not change the result).

  compare.py shells CLI.jsonl REF.jsonl [N|- [DEFAULT.jsonl]]
      Compares the "shellList" and "defects" of `info --json --shells --defects
      [--max-defects N]` with the reference's (run with --shells --defects and the
      default of 1000 items): the same keys in the same order, integers, strings,
      booleans and nulls equal, floats within the relative tolerance. With N, the
      reference's lists are first cut to N items (and each hole's vertex list and
      each seam's cutEdges to N entries), as the CLI must have done ('-': no
      cut). With DEFAULT.jsonl (the CLI's plain `info --json`), also checks that
      the other keys are the default output's and that the default output has
      neither shellList nor defects.

  compare.py manifest REF.jsonl
      Cross-checks the reference itself against the numbers that
      shared/fixtures/MANIFEST.md states for each fixture. Those numbers were
      produced by an independent script (and, where quoted, by the source
      projects' own tests), so they are hard-coded here: nothing reads the shared
      directory at test time.

The MANIFEST's `loops` counts connected components of the boundary-edge graph.
That equals holes + seams only when the mesh has no pinch vertices on its
boundary and no cut (inconsistent or non-manifold) sides, so `loops` is only
compared in that case. Where the MANIFEST lists pinch vertices, the fan rule of
the topology contract must give at least one hole per boundary component.
"""

import json
import math
import sys

# file (relative to tests/fixtures) -> numbers from MANIFEST.md.
#   V, E, bnd, nm: vertices (exact weld), undirected edges, boundary edges, non-manifold edges
#   loops: boundary-edge-graph components; chi; parts: edge-connected parts
#   inc: inconsistently oriented edges; collapsed: degenerate triangles
#   pinch/bcomp: pinch vertices / boundary components (then loops is not exact)
#   mismatch: facets whose stored normal opposes the winding
MANIFEST = {
    'wolph_numpy-stl/tests/stl_ascii/Cube.stl':
        dict(format='ascii', solids=[('PRO2STL version 1.0', 12)], tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl':
        dict(format='ascii', solids=[('HalfDonut.stl', 288)], tris=288, V=144, E=432, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_ascii/Moon.stl':
        dict(format='ascii', solids=[('Moon.stl', 116)], tris=116, V=60, E=174, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_ascii/Moon_Chinese.stl':
        dict(format='ascii', solids=[('月球', 116)], tris=116, V=60, E=174, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_ascii/Star.stl':
        dict(format='ascii', solids=[('Star.stl', 68)], tris=68, V=36, E=102, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/Cube.stl':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/CubeInvalidUnicode.stl':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/HalfDonut.stl':
        dict(format='binary', tris=288, V=144, E=432, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/Moon.stl':
        dict(format='binary', tris=116, V=60, E=174, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/Star.stl':
        dict(format='binary', tris=68, V=36, E=102, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/StarWithEmptyHeader.stl':
        dict(format='binary', tris=68, V=36, E=102, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_binary/rear_case.stl':
        dict(format='binary', tris=18808, V=9404, E=28212, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_tests/bwb.stl':
        dict(format='ascii', solids=[('"bwb"', 4464)], tris=4464, V=2234, E=6696, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0, mismatch=155),
    'wolph_numpy-stl/tests/stl_tests/dos.stl':
        dict(format='ascii', solids=[('Moon.stl', 116)], tris=116, V=60, E=174, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/stl_tests/triamid.stl':
        dict(format='binary', tris=10, V=7, E=15, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=13),
    'wolph_numpy-stl/tests/stl_tests/unix.stl':
        dict(format='ascii', solids=[('Moon.stl', 116)], tris=116, V=60, E=174, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'wolph_numpy-stl/tests/tmp/test_args_False_0/binary.stl':
        dict(),
    'assimp_assimp/_history/a8a1ca98/test/models/STL/3DSMaxExport.STL':
        dict(),
    'assimp_assimp/test/models/STL/3DSMaxExport.STL':
        dict(format='binary', tris=2000, V=1042, E=2992, bnd=0, nm=16, loops=0, chi=50, parts=24),
    'assimp_assimp/test/models/STL/Spider_ascii.stl':
        dict(format='ascii', solids=[('NoName_1', 1368)], tris=1368, V=722, E=2004, bnd=72, nm=0, loops=6, chi=30, parts=18, inc=10, collapsed=56, mismatch=1312),
    'assimp_assimp/test/models/STL/Spider_binary.stl':
        dict(format='binary', tris=1368, V=722, E=2004, bnd=72, nm=0, loops=6, chi=30, parts=18, inc=10, collapsed=56, mismatch=1312),
    'assimp_assimp/test/models/STL/Wuson.stl':
        dict(format='binary', tris=3732, V=2117, E=5804, bnd=412, nm=0, chi=45, parts=54, pinch=2, bcomp=52),
    'assimp_assimp/test/models/STL/formatDetection':
        dict(format='ascii', solids=[('testTriangle', 1)], tris=1, V=3, E=3, bnd=3, nm=0, loops=1, chi=1, parts=1),
    'assimp_assimp/test/models/STL/sphereWithHole.stl':
        dict(format='ascii', solids=[('tinysphere_withhole', 285)], tris=285, V=146, E=432, bnd=9, nm=0, chi=-1, parts=1, pinch=2, bcomp=1),
    'assimp_assimp/test/models/STL/triangle.stl':
        dict(format='ascii', solids=[('testTriangle', 1)], tris=1, V=3, E=3, bnd=3, nm=0, loops=1, chi=1, parts=1),
    'assimp_assimp/test/models/STL/triangle_with_empty_solid.stl':
        dict(format='ascii', solids=[('testTriangle', 1), ('emptySolid', 0)], tris=1, V=3, E=3, bnd=3, nm=0, loops=1, chi=1, parts=1),
    'assimp_assimp/test/models/STL/triangle_with_two_solids.stl':
        dict(format='ascii', solids=[('testTriangle_1', 1), ('testTriangle_2', 1)], tris=2, V=6, E=6, bnd=6, nm=0, loops=2, chi=2, parts=2),
    'mikedh_trimesh/models/1002_tray_bottom.STL':
        dict(format='ascii', solids=[('1002_tray_bottom', 4520)], tris=4520, V=2216, E=6780, bnd=0, nm=0, loops=0, chi=-44, parts=1, inc=0),
    'mikedh_trimesh/models/20mm-xyz-cube.stl':
        dict(format='binary', tris=260, V=132, E=390, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/7_8ths_cube.stl':
        dict(format='binary', tris=24, V=14, E=36, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/ADIS16480.STL':
        dict(format='ascii', solids=[('ci - ADIS16480-1', 7436)], tris=7436, V=3672, E=11154, bnd=0, nm=0, loops=0, chi=-46, parts=1, inc=0),
    'mikedh_trimesh/models/angle_block.STL':
        dict(format='binary', tris=704, V=398, E=1139, bnd=166, nm=0, chi=-37, parts=1, pinch=33, bcomp=4),
    'mikedh_trimesh/models/ascii.stl.zip.extracted/fuji_obj.stl':
        dict(format='ascii', solids=[('solidname', 344)], tris=344, V=174, E=516, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/box.STL':
        dict(format='binary', tris=8954, V=4455, E=13431, bnd=0, nm=0, loops=0, chi=-22, parts=10, inc=0),
    'mikedh_trimesh/models/busted.STL':
        dict(format='binary', tris=3878, V=1941, E=5817, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/counter.unitsmm.STL':
        dict(format='binary', tris=83750, V=41837, E=125625, bnd=0, nm=0, loops=0, chi=-38, parts=6, inc=0),
    'mikedh_trimesh/models/cylinder.stl':
        dict(format='binary', tris=416, V=210, E=624, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/empty.stl':
        dict(format='ascii', solids=[('Empty', 0)], tris=0),
    'mikedh_trimesh/models/emptyIO/stl_empty_ascii.stl':
        dict(format='ascii', solids=[('Exported from Blender-2.91.0', 0)], tris=0),
    'mikedh_trimesh/models/emptyIO/stl_empty_bin.stl':
        dict(format='binary', tris=0),
    'mikedh_trimesh/models/featuretype.STL':
        dict(format='binary', tris=3476, V=2010, E=5502, bnd=576, nm=0, loops=16, chi=-16, parts=1),
    'mikedh_trimesh/models/idler_riser.STL':
        dict(format='binary', tris=1572, V=803, E=2380, bnd=44, nm=0, chi=-5, parts=3, pinch=1, bcomp=3),
    'mikedh_trimesh/models/large_block.STL':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/large_block_obb.STL':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/multibody.stl':
        dict(format='ascii', solids=[('bodyB', 12), ('bodyA', 20)], tris=32, V=20, E=48, bnd=0, nm=0, loops=0, chi=4, parts=2, inc=12),
    'mikedh_trimesh/models/octagonal_pocket.stl':
        dict(format='binary', tris=3262, V=1658, E=4920, bnd=54, nm=0, chi=0, parts=5, pinch=3, bcomp=2),
    'mikedh_trimesh/models/origin_inside.STL':
        dict(format='binary', tris=28, V=16, E=42, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/plate_holes.STL':
        dict(format='binary', tris=1252, V=618, E=1878, bnd=0, nm=0, loops=0, chi=-8, parts=1, inc=0),
    'mikedh_trimesh/models/round.stl':
        dict(format='binary', tris=1120, V=560, E=1680, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'mikedh_trimesh/models/shared.STL':
        dict(format='binary', tris=24, V=14, E=35, bnd=0, nm=1, loops=0, chi=3, parts=1),
    'mikedh_trimesh/models/soup.stl':
        dict(format='binary', tris=100, V=300, E=300, bnd=300, nm=0, loops=100, chi=100, parts=100),
    'mikedh_trimesh/models/teapot.stl':
        dict(format='binary', tris=894, V=480, E=1373, bnd=64, nm=0, loops=6, chi=1, parts=4),
    'mikedh_trimesh/models/torus.STL':
        dict(format='binary', tris=8700, V=4350, E=13050, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'mikedh_trimesh/models/two_objects_mixed_case_names.stl':
        dict(format='ascii', solids=[('CubeExportedFromCAD', 12), ('TranslatedCubeExportedFromCAD', 12)], tris=24, V=16, E=36, bnd=0, nm=0, loops=0, chi=4, parts=2, inc=0),
    'mikedh_trimesh/models/unit_cube.STL':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'mikedh_trimesh/models/unit_sphere.STL':
        dict(format='binary', tris=1280, V=642, E=1920, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl':
        dict(format='ascii', solids=[('', 15048)], tris=15048, V=7526, E=22572, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'Pix4D_OpenMesh/src/Unittests/TestFiles/cube1Binary.stl':
        dict(format='binary', tris=15048, V=7526, E=22572, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'amandaghassaei_stl-parser/test/stl/chair.stl':
        dict(format='binary', tris=21760, V=10882, E=32640, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'amandaghassaei_stl-parser/test/stl/cubeAscii.stl':
        dict(format='ascii', solids=[('ASCII', 12)], tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'amandaghassaei_stl-parser/test/stl/cubeBinary.stl':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'amandaghassaei_stl-parser/test/stl/skull.stl':
        dict(format='binary', tris=2538, V=1327, E=3813, bnd=12, nm=0, loops=3, chi=52, parts=34),
    'amandaghassaei_stl-parser/test/stl/teapot.stl':
        dict(format='binary', tris=9438, V=4719, E=14157, bnd=0, nm=0, loops=0, chi=0, parts=1, inc=0),
    'amandaghassaei_stl-parser/test/stl/wrench.stl':
        dict(format='binary', tris=65502, V=32740, E=98247, bnd=0, nm=6, loops=0, chi=-5, parts=3),
    'google_draco/testdata/STL/bunny.stl':
        dict(format='binary', tris=69451, V=34834, E=104288, bnd=223, nm=0, loops=5, chi=-3, parts=1),
    'google_draco/testdata/STL/test_sphere.stl':
        dict(format='binary', tris=224, V=114, E=336, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'google_draco/testdata/STL/test_sphere_ascii.stl':
        dict(format='ascii', solids=[('Exported from Blender-3.0.1', 224)], tris=224, V=114, E=336, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'nmwsharp_geometry-central/test/assets/stl_box_ascii.stl':
        dict(format='ascii', solids=[('"Design1<stl unit=MM>"', 12)], tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'nmwsharp_geometry-central/test/assets/stl_box_binary.stl':
        dict(format='binary', tris=12, V=8, E=18, bnd=0, nm=0, loops=0, chi=2, parts=1, inc=0),
    'hmeyer_stl_io/src/testdata/bunny_99.stl':
        dict(format='binary', tris=99, V=54, E=152, bnd=7, nm=0, loops=1, chi=1, parts=1),
    'hmeyer_stl_io/src/testdata/bunny_99_ascii.stl':
        dict(format='ascii', solids=[('vcg', 99)], tris=99, V=54, E=152, bnd=7, nm=0, loops=1, chi=1, parts=1),
}

# Further facts the MANIFEST states in prose (and the source projects' tests).
MANIFEST_FACTS = {
    'assimp_assimp/_history/a8a1ca98/test/models/STL/3DSMaxExport.STL': dict(error='truncated'),
    'wolph_numpy-stl/tests/tmp/test_args_False_0/binary.stl': dict(error='empty'),
    'wolph_numpy-stl/tests/stl_binary/HalfDonut.stl': dict(warnings=['trailing-bytes'], volume=2.343149),
    'wolph_numpy-stl/tests/stl_ascii/HalfDonut.stl': dict(warnings=[], volume=2.343149),
    'wolph_numpy-stl/tests/stl_ascii/Moon.stl': dict(volume=0.888723),
    'wolph_numpy-stl/tests/stl_binary/Moon.stl': dict(volume=0.888723),
    'wolph_numpy-stl/tests/stl_ascii/Star.stl': dict(volume=1.416599),
    'wolph_numpy-stl/tests/stl_binary/Star.stl': dict(volume=1.416599),
    'wolph_numpy-stl/tests/stl_binary/StarWithEmptyHeader.stl': dict(volume=1.416599),
    'Pix4D_OpenMesh/src/Unittests/TestFiles/cube1.stl': dict(warnings=['missing-endsolid']),
    'amandaghassaei_stl-parser/test/stl/cubeBinary.stl': dict(colors='magics'),
    'mikedh_trimesh/models/20mm-xyz-cube.stl': dict(colors='magics'),
    'assimp_assimp/test/models/STL/Wuson.stl': dict(colors='none'),
    'amandaghassaei_stl-parser/test/stl/wrench.stl': dict(colors='none'),
    'mikedh_trimesh/models/unit_cube.STL': dict(volume=1.0),
    'mikedh_trimesh/models/featuretype.STL': dict(volume=11.627733431196749),
    'hmeyer_stl_io/src/testdata/bunny_99.stl': dict(area=0.04998364),
}

CONTRACT_KEYS = ['file', 'format', 'solids', 'triangles', 'vertices', 'degenerateTriangles',
                 'colors', 'normalMismatches', 'bbox', 'area', 'volume', 'warnings', 'edges',
                 'boundaryEdges', 'nonManifoldEdges', 'inconsistentEdges', 'nonManifoldVertices',
                 'holes', 'seams', 'holeSizes', 'shells', 'eulerCharacteristic', 'genus',
                 'watertight', 'manifold']
FLOAT_KEYS = {'area', 'volume'}
REL_TOL = 1e-6


def load(path):
    out = {}
    order = []
    with open(path, encoding='utf-8') as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            try:
                obj = json.loads(line, object_pairs_hook=lambda kv: dict(kv))
                keys = list(json.loads(line, object_pairs_hook=lambda kv: [k for k, _ in kv]))
            except ValueError as e:
                out.setdefault('__invalid__', []).append('%s:%d: invalid JSON (%s): %s'
                                                         % (path, n, e, line[:200]))
                continue
            if not isinstance(obj, dict) or 'file' not in obj:
                out.setdefault('__invalid__', []).append('%s:%d: not an object with "file"' % (path, n))
                continue
            obj['__keys__'] = keys
            out[obj['file']] = obj
            order.append(obj['file'])
    return out, order


def rel_key(path):
    marker = 'tests/fixtures/'
    i = path.find(marker)
    return path[i + len(marker):] if i >= 0 else path


def close(a, b, scale=0.0):
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
        return False
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= REL_TOL * max(abs(a), abs(b)) + scale


def same_int(a, b):
    return (type(a) is int and type(b) is int and a == b)


def compare_obj(cli, ref):
    """Returns a list of difference lines (empty when they agree)."""
    d = []
    if 'error' in ref or 'error' in cli:
        if 'error' not in ref:
            d.append('CLI failed with %s, reference read it (%s %s triangles)'
                     % (json.dumps(cli['error'], ensure_ascii=False), ref.get('format'),
                        ref.get('triangles')))
        elif 'error' not in cli:
            d.append('reference failed with %s, CLI read it (%s %s triangles)'
                     % (json.dumps(ref['error'], ensure_ascii=False), cli.get('format'),
                        cli.get('triangles')))
        else:
            ce, re_ = cli['error'], ref['error']
            if not isinstance(ce, dict) or ce.get('code') != re_.get('code'):
                d.append('error code: CLI %r, reference %r' % (ce.get('code') if isinstance(ce, dict) else ce,
                                                               re_.get('code')))
            elif not isinstance(ce.get('message'), str) or not ce.get('message'):
                d.append('error without a message')
        return d
    keys = cli['__keys__']
    missing = [k for k in CONTRACT_KEYS if k not in cli]
    if missing:
        d.append('missing keys: %s' % ', '.join(missing))
    present = [k for k in keys if k in CONTRACT_KEYS]
    if present != [k for k in CONTRACT_KEYS if k in cli]:
        d.append('key order differs from the contract: %s' % ', '.join(keys))
    area = ref.get('area') or 0.0
    for k in CONTRACT_KEYS:
        if k == 'file' or k not in cli:
            continue
        a, b = cli[k], ref[k]
        if k in FLOAT_KEYS:
            scale = 1e-12 + (1e-9 * abs(area) ** 1.5 if k == 'volume' else 1e-12 * abs(area))
            ok = close(a, b, scale) and not isinstance(a, bool)
        elif k == 'bbox':
            if a is None or b is None:
                ok = a is None and b is None
            else:
                try:
                    ok = all(len(a[m]) == 3 and all(close(x, y, 1e-30) for x, y in zip(a[m], b[m]))
                             for m in ('min', 'max'))
                except (TypeError, KeyError):
                    ok = False
        elif k == 'warnings':
            try:
                ca = sorted(w['code'] for w in a)
                cb = sorted(w['code'] for w in b)
                ok = ca == cb and all(isinstance(w.get('message'), str) for w in a)
                a, b = ca, cb
            except (TypeError, KeyError):
                ok = False
        elif k == 'solids':
            try:
                ok = len(a) == len(b) and all(x['name'] == y['name'] and same_int(x['triangles'], y['triangles'])
                                              for x, y in zip(a, b))
                if not ok and any(len(x['name']) > 60 for x in a + b):
                    # long names: show their UTF-8 length and ending instead
                    a = [['%d bytes ...%s' % (len(x['name'].encode()), x['name'][-12:]), x['triangles']] for x in a]
                    b = [['%d bytes ...%s' % (len(x['name'].encode()), x['name'][-12:]), x['triangles']] for x in b]
            except (TypeError, KeyError):
                ok = False
        elif k == 'genus':
            ok = (a is None and b is None) or (a is not None and b is not None and close(a, b))
        elif isinstance(b, bool):
            ok = a is b
        elif isinstance(b, int):
            ok = same_int(a, b)
        else:
            ok = a == b
        if not ok:
            sa = json.dumps(a, ensure_ascii=False)
            sb = json.dumps(b, ensure_ascii=False)
            if len(sa) > 300:
                sa = sa[:300] + '...'
            if len(sb) > 300:
                sb = sb[:300] + '...'
            d.append('%s: CLI %s, reference %s' % (k, sa, sb))
    return d


def load_rc(path):
    rc = {}
    with open(path, encoding='utf-8') as f:
        for line in f:
            line = line.rstrip('\n')
            if line:
                status, name = line.split('\t', 1)
                rc[name] = int(status)
    return rc


def cmd_cli(cli_path, ref_path, rc_path=None):
    cli, cli_order = load(cli_path)
    ref, ref_order = load(ref_path)
    rc = load_rc(rc_path) if rc_path else {}
    bad = 0
    for line in cli.get('__invalid__', []):
        print('CLI output: ' + line)
        bad += 1
    for f in ref_order:
        if f not in cli:
            print('== %s\n   no CLI output for this file' % f)
            bad += 1
            continue
        diffs = compare_obj(cli[f], ref[f])
        if f in rc:
            want = 1 if 'error' in ref[f] else 0
            if rc[f] != want:
                diffs.append('exit status %d, expected %d' % (rc[f], want))
        if diffs:
            bad += 1
            print('== %s' % f)
            for x in diffs:
                print('   ' + x)
    extra = [f for f in cli_order if f not in ref]
    for f in extra:
        print('== %s\n   CLI printed a file the reference did not see' % f)
        bad += 1
    n = len(ref_order)
    print('compared %d files: %d differ' % (n, bad))
    return 1 if bad else 0


def cmd_manifest(ref_path):
    ref, order = load(ref_path)
    bad = 0
    checked = 0
    for f in order:
        key = rel_key(f)
        if key not in MANIFEST:
            continue
        checked += 1
        m = MANIFEST[key]
        facts = MANIFEST_FACTS.get(key, {})
        r = ref[f]
        diffs = []
        if 'error' in facts:
            if 'error' not in r or r['error']['code'] != facts['error']:
                diffs.append('expected error %s, got %s' % (facts['error'], r.get('error')))
        elif 'error' in r:
            diffs.append('unexpected error %s' % r['error'])
        else:
            def chk(name, mv, rv):
                if mv != rv:
                    diffs.append('%s: MANIFEST %r, reference %r' % (name, mv, rv))
            if 'format' in m:
                chk('format', m['format'], r['format'])
            if 'tris' in m:
                chk('triangles', m['tris'], r['triangles'])
            if 'solids' in m:
                chk('solids', [list(s) for s in m['solids']],
                    [[s['name'], s['triangles']] for s in r['solids']])
            for mk, rk in (('V', 'vertices'), ('E', 'edges'), ('bnd', 'boundaryEdges'),
                           ('nm', 'nonManifoldEdges'), ('chi', 'eulerCharacteristic'),
                           ('parts', 'shells'), ('inc', 'inconsistentEdges'),
                           ('collapsed', 'degenerateTriangles'), ('mismatch', 'normalMismatches')):
                if mk in m:
                    chk(mk, m[mk], r[rk])
            if 'V' in m and 'collapsed' not in m:
                chk('collapsed', 0, r['degenerateTriangles'])
            if 'loops' in m and 'pinch' not in m and m.get('inc', 1) == 0 and m.get('nm', 1) == 0:
                chk('loops (holes+seams)', m['loops'], r['holes'] + r['seams'])
                chk('seams', 0, r['seams'])
            if 'pinch' in m:
                if r['holes'] < m['bcomp']:
                    diffs.append('fewer fan-rule holes (%d) than boundary components (%d)'
                                 % (r['holes'], m['bcomp']))
                if sum(r['holeSizes']) != m['bnd']:
                    diffs.append('hole sizes sum to %d, MANIFEST bnd=%d' % (sum(r['holeSizes']), m['bnd']))
            if 'bnd' in m and m.get('inc', 1) == 0 and m.get('nm', 1) == 0:
                chk('sum(holeSizes)', m['bnd'], sum(r['holeSizes']))
            if 'warnings' in facts:
                chk('warnings', sorted(facts['warnings']), sorted(w['code'] for w in r['warnings']))
            if 'colors' in facts:
                chk('colors', facts['colors'], r['colors'])
            for k in ('volume', 'area'):
                if k in facts and abs(facts[k] - r[k]) > 1e-5 * max(1.0, abs(facts[k])):
                    diffs.append('%s: MANIFEST/source %r, reference %r' % (k, facts[k], r[k]))
        if diffs:
            bad += 1
            print('== %s' % key)
            for x in diffs:
                print('   ' + x)
    missing = [k for k in MANIFEST if k not in {rel_key(f) for f in order}]
    for k in missing:
        print('== %s\n   listed in the MANIFEST but not checked (no reference output)' % k)
    print('reference vs MANIFEST: checked %d files, %d disagree, %d not run'
          % (checked, bad, len(missing)))
    return 1 if bad or missing else 0


def tree_diff(a, b, where, out):
    """Differences between two JSON values: keys in order, numbers within REL_TOL
    (an integer printed without a fraction may stand for a float)."""
    if len(out) > 20:
        return
    if isinstance(b, dict):
        if not isinstance(a, dict) or list(a) != list(b):
            out.append('%s: keys %s, reference %s' % (where, list(a) if isinstance(a, dict) else type(a).__name__,
                                                      list(b)))
            return
        for k in b:
            tree_diff(a[k], b[k], where + '.' + k, out)
    elif isinstance(b, list):
        if not isinstance(a, list) or len(a) != len(b):
            out.append('%s: length %s, reference %d' % (where, len(a) if isinstance(a, list) else type(a).__name__,
                                                       len(b)))
            return
        for i, (x, y) in enumerate(zip(a, b)):
            tree_diff(x, y, '%s[%d]' % (where, i), out)
    elif isinstance(b, bool) or b is None or isinstance(b, str):
        if type(a) is not type(b) or a != b:
            out.append('%s: CLI %r, reference %r' % (where, a, b))
    elif isinstance(b, int) and isinstance(a, int) and not isinstance(a, bool):
        if a != b:
            out.append('%s: CLI %r, reference %r' % (where, a, b))
    elif not close(a, b, 1e-12) or isinstance(a, bool):
        out.append('%s: CLI %r, reference %r' % (where, a, b))


def cut_reference(ref, n):
    """The reference's defect lists as `--max-defects n` prints them."""
    out = {}
    for kind, v in ref.items():
        if v is None:  # selfIntersections without --intersections
            out[kind] = None
            continue
        items = []
        for it in v['items'][:n]:
            it = dict(it)
            for k in ('vertices', 'cutEdges'):
                if kind in ('holes', 'seams') and k in it:
                    it[k] = it[k][:n]
            items.append(it)
        out[kind] = {'count': v['count'], 'items': items}
    return out


def cmd_shells(cli_path, ref_path, n=None, default_path=None):
    cli, _ = load(cli_path)
    ref, ref_order = load(ref_path)
    default = load(default_path)[0] if default_path else None
    bad = 0
    for line in cli.get('__invalid__', []):
        print('CLI output: ' + line)
        bad += 1
    for f in ref_order:
        r = ref[f]
        c = cli.get(f)
        diffs = []
        if c is None:
            diffs.append('no CLI output for this file')
        elif 'error' in r or 'error' in c:
            if ('error' in r) != ('error' in c):
                diffs.append('error in only one of them')
        else:
            for k in ('shellList', 'defects'):
                if k not in c:
                    diffs.append('no "%s"' % k)
                    continue
                want = cut_reference(r[k], int(n)) if k == 'defects' and n is not None else r[k]
                tree_diff(c[k], want, k, diffs)
            if c['__keys__'][-2:] != ['shellList', 'defects']:
                diffs.append('shellList and defects are not the last keys: %s' % c['__keys__'])
            if default is not None:
                d = default.get(f)
                rest = {k: v for k, v in c.items() if k not in ('shellList', 'defects', '__keys__')}
                base = {k: v for k, v in (d or {}).items() if k != '__keys__'}
                if rest != base:
                    diffs.append('the other keys differ from the default output')
                if d is not None and ('shellList' in d or 'defects' in d):
                    diffs.append('the default output has shellList or defects')
        if diffs:
            bad += 1
            print('== %s' % f)
            for x in diffs:
                print('   ' + x)
    print('compared shells and defects of %d files%s: %d differ'
          % (len(ref_order), '' if n is None else ' (--max-defects %s)' % n, bad))
    return 1 if bad else 0


def cmd_same(a_path, b_path):
    bad = 0
    with open(a_path, encoding='utf-8') as fa, open(b_path, encoding='utf-8') as fb:
        la = [x for x in fa.read().split('\n') if x.strip()]
        lb = [x for x in fb.read().split('\n') if x.strip()]
    if len(la) != len(lb):
        print('%s has %d lines, %s has %d' % (a_path, len(la), b_path, len(lb)))
        bad += 1
    for x, y in zip(la, lb):
        try:
            ox, oy = json.loads(x), json.loads(y)
        except ValueError:
            print('invalid JSON line:\n  %s\n  %s' % (x[:200], y[:200]))
            bad += 1
            continue
        fx, fy = ox.pop('file', None), oy.pop('file', None)
        if ox != oy:
            bad += 1
            keys = sorted(k for k in set(ox) | set(oy) if ox.get(k) != oy.get(k))
            print('== %s vs %s: differ in %s' % (fx, fy, ', '.join(keys)))
    return 1 if bad else 0


def main(argv):
    if len(argv) in (3, 4) and argv[0] == 'cli':
        return cmd_cli(*argv[1:])
    if len(argv) == 3 and argv[0] == 'same':
        return cmd_same(argv[1], argv[2])
    if len(argv) in (3, 4, 5) and argv[0] == 'shells':
        n = argv[3] if len(argv) >= 4 and argv[3] != '-' else None
        return cmd_shells(argv[1], argv[2], n, argv[4] if len(argv) == 5 else None)
    if len(argv) == 2 and argv[0] == 'manifest':
        return cmd_manifest(argv[1])
    sys.stderr.write(__doc__)
    return 2


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')
    sys.exit(main(sys.argv[1:]))

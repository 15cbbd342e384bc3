#!/usr/bin/env python3
"""Writes the fuzz seed corpus: tests/fuzz/seeds/<target>/.

Raw STL seeds (generated here, a few small files from tests/fixtures and every file in
tests/fixtures/regress) go to
seeds/fuzz_whole/. The other targets take a few parameter bytes in front of the STL
bytes, so their seeds are the same files with prefixes:
  fuzz_stream:    [flags][n chunk sizes]   (n = (flags & 7) + 1)
  fuzz_tolerance: [mode][mantissa]         (see fuzz_tolerance.cpp)
  fuzz_edit:      [base][parameters][edit bytes] (see fuzz_edit.cpp): generated bases and
                  the small STL seeds (base 3 or 7, a 2-byte length), with random edit bytes
fuzz_number takes up to 9 number tokens separated by spaces (NUMBER_SEEDS).
Run again after changing it: python3 tests/fuzz/make_seeds.py
"""
import math
import random
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SEEDS = os.path.join(HERE, "seeds")

FIXTURES = [  # small files from tests/fixtures (<= 20 KB)
    "assimp_assimp/test/models/STL/triangle.stl",
    "assimp_assimp/test/models/STL/triangle_with_two_solids.stl",
    "assimp_assimp/test/models/STL/triangle_with_empty_solid.stl",
    "wolph_numpy-stl/tests/stl_tests/triamid.stl",
    "wolph_numpy-stl/tests/stl_binary/CubeInvalidUnicode.stl",
    "nmwsharp_geometry-central/test/assets/stl_box_ascii.stl",
    "mikedh_trimesh/models/7_8ths_cube.stl",
    "mikedh_trimesh/models/empty.stl",
    "mikedh_trimesh/models/emptyIO/stl_empty_ascii.stl",
    "hmeyer_stl_io/src/testdata/bunny_99.stl",
    "mikedh_trimesh/models/soup.stl",
]


def cube(o=(0, 0, 0), s=1.0):
    v = [(o[0] + s * (i & 1), o[1] + s * ((i >> 1) & 1), o[2] + s * ((i >> 2) & 1)) for i in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    f = []
    for a, b, c, d in quads:
        f += [(a, b, c), (a, c, d)]
    return v, f


def torus(n, m, skip=(), R=3.0, r=1.0):
    v = []
    for i in range(n):
        for j in range(m):
            u, w = 2 * math.pi * i / n, 2 * math.pi * j / m
            v.append(((R + r * math.cos(w)) * math.cos(u), (R + r * math.cos(w)) * math.sin(u), r * math.sin(w)))
    idx = lambda i, j: (i % n) * m + (j % m)
    f = []
    for i in range(n):
        for j in range(m):
            if i * m + j in skip:
                continue
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            f += [(a, b, c), (a, c, d)]
    return v, f


def normal(v, t):
    a, b, c = (v[k] for k in t)
    u = [b[i] - a[i] for i in range(3)]
    w = [c[i] - a[i] for i in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    l = math.sqrt(sum(x * x for x in n)) or 1.0
    return tuple(x / l for x in n)


def binary(mesh, header=b"stltopo fuzz seed", attrs=None, count=None):
    v, f = mesh
    out = bytearray(header[:80].ljust(80, b"\0"))
    out += struct.pack("<I", len(f) if count is None else count)
    for k, t in enumerate(f):
        out += struct.pack("<3f", *normal(v, t))
        for c in t:
            out += struct.pack("<3f", *v[c])
        out += struct.pack("<H", attrs[k] if attrs else 0)
    return bytes(out)


def ascii(mesh, name="seed", nl="\n", end=True, fmt="%.9g"):
    v, f = mesh
    s = "solid " + name + nl
    for t in f:
        s += "  facet normal " + " ".join(fmt % x for x in normal(v, t)) + nl + "    outer loop" + nl
        for c in t:
            s += "      vertex " + " ".join(fmt % x for x in v[c]) + nl
        s += "    endloop" + nl + "  endfacet" + nl
    if end:
        s += "endsolid " + name + nl
    return s.encode()


def facet(a, b, c, n="0 0 1"):
    return "facet normal %s\n outer loop\n  vertex %s\n  vertex %s\n  vertex %s\n endloop\nendfacet\n" % (n, a, b, c)


def generated():
    c = cube()
    t = torus(6, 4, skip=(3, 9))
    seeds = {}
    seeds["bin_cube.stl"] = binary(c)
    seeds["bin_torus_holes.stl"] = binary(t)
    seeds["bin_concat.stl"] = binary(c, b"first") + binary(cube((1, 0, 0)), b"second") + b"\n"
    seeds["bin_solid_header.stl"] = binary(c, b"solid looks like ascii")
    seeds["bin_trailing.stl"] = binary(c) + b"z" * 40
    seeds["bin_truncated.stl"] = binary(c)[:84 + 50 * 5 + 20]
    seeds["bin_count_zero_body.stl"] = binary(([], []), b"zero") + b"\1" * 50
    seeds["bin_count_huge.stl"] = binary(c, count=0xFFFFFFFF)
    seeds["bin_magics.stl"] = binary(c, b"COLOR=\x0a\x14\x1e\xff MATERIAL=abcdefghijkl",
                                     attrs=[0x8000] * 6 + [31 | (16 << 5)] * 6)
    seeds["bin_viscam.stl"] = binary(c, b"no colour header", attrs=[0x8000 | (31 << 10) | 1] * 12)
    nan = bytearray(binary(c))
    nan[84 + 50 * 7 + 16:84 + 50 * 7 + 20] = struct.pack("<f", float("nan"))
    seeds["bin_nan.stl"] = bytes(nan)
    nonman = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (1, 1, 1)],
              [(0, 1, 2), (1, 0, 3), (0, 1, 4), (2, 1, 5), (2, 1, 5)])
    seeds["bin_nonmanifold.stl"] = binary(nonman)
    seeds["bin_ff.stl"] = b"\xff" * 200
    seeds["bin_degenerate.stl"] = binary(([(0, 0, 0), (1, 0, 0), (-0.0, 0, 0)], [(0, 1, 2), (0, 0, 1), (0, 1, 0)]))
    near = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1e-6, 0, 0), (1, 1e-6, 0), (1, 1, 0)], [(0, 1, 2), (4, 3, 5)])
    seeds["bin_near_vertices.stl"] = binary(near)
    seeds["ascii_cube.stl"] = ascii(c)
    seeds["ascii_torus_crlf.stl"] = ascii(torus(4, 3), "crlf", nl="\r\n")
    seeds["ascii_cr_only.stl"] = ascii(c, "cr", nl="\r")
    seeds["ascii_no_endsolid.stl"] = ascii(c, "open", end=False)
    seeds["ascii_bom_mixed_case.stl"] = (
        b"\xef\xbb\xbf  \t\r\nSOLID  Mixed Name  \r\n  FaCeT NoRmAl 0 0 1\r  OUTER\tLOOP\n"
        b"VERTEX 0 0 0 vertex 1 0 0\n vertex 0 1 0\n ENDLOOP trailing words\n ENDFACET more\nEndSolid Mixed\n")
    seeds["ascii_two_solids.stl"] = ("solid a\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid a\nsolid \xe6\x9c\x88\nendsolid\n").encode("latin-1")
    seeds["ascii_numbers.stl"] = ("solid n\n" + facet("0x1p3 -0 +1.5", ".5 1. 1E+02", "-1.25e-3 7e-46 16777217")
                                  + facet("3.4028234e38 1.17549435e-38 0.1000000000000000055511151231257827",
                                          "123456789012345678901234567890 0 0", "1e-45 1e38 -1e38") + "endsolid\n").encode()
    seeds["ascii_1e999.stl"] = ("solid big\n" + facet("1e999 0 0", "1 0 0", "0 1 0") + "endsolid\n").encode()
    seeds["ascii_nan_inf.stl"] = ("solid x\n" + facet("nan 0 0", "inf 0 0", "-INFINITY 0 0") + "endsolid\n").encode()
    seeds["ascii_unexpected_end.stl"] = ("solid x\n" + facet("0 0 0", "1 0 0", "0 1 0") + "facet normal 0 0 1\n outer loop\n vertex 1 2 3\n").encode()
    seeds["ascii_four_vertices.stl"] = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid\n"
    seeds["ascii_bad_number.stl"] = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1,5 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n"
    seeds["ascii_long_name.stl"] = ("solid " + "n" * 4200 + "\n" + facet("0 0 0", "1 0 0", "0 1 0") + "endsolid\n").encode()
    seeds["ascii_long_number.stl"] = ("solid x\nfacet normal 0 0 1\nouter loop\nvertex " + "7" * 5000 + " 0 0\n").encode()
    seeds["ascii_empty_solid.stl"] = b"solid empty\nendsolid empty"
    seeds["ascii_solid_binary_body.stl"] = b"solid x\n" + binary(c)[8:]
    seeds["ascii_no_normal.stl"] = b"solid x\nfacet outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 1 0 endloop endfacet endsolid x\n"
    seeds["ascii_tol.stl"] = ascii(near, "near")
    seeds["empty.stl"] = b""
    seeds["short.stl"] = b"hello world, this is not an STL file"
    return seeds


def main():
    raw = generated()
    for rel in FIXTURES:
        path = os.path.join(ROOT, "tests", "fixtures", rel)
        with open(path, "rb") as fh:
            data = fh.read()
        assert len(data) <= 20000, rel
        raw["fx_" + rel.replace("/", "_")] = data
    regress = os.path.join(ROOT, "tests", "fixtures", "regress")
    for name in sorted(os.listdir(regress)):  # every regression input is a seed too
        path = os.path.join(regress, name)
        if name.endswith(".md") or not os.path.isfile(path) or os.path.getsize(path) > 20000:
            continue
        with open(path, "rb") as fh:
            raw["regress_" + name] = fh.read()
    shutil.rmtree(SEEDS, ignore_errors=True)
    dirs = {t: os.path.join(SEEDS, t) for t in ("fuzz_whole", "fuzz_stream", "fuzz_tolerance", "fuzz_number", "fuzz_edit")}
    for d in dirs.values():
        os.makedirs(d)
    # Stream prefixes: (flags, chunk sizes); the flags select options (see fuzz_stream.cpp).
    chunkings = [(0x00, [1]), (0x01 | 0x10, [7, 50]), (0x02 | 0x08 | 0x40, [84, 0, 3]), (0x03 | 0x20, [255, 1, 13, 2])]
    # Tolerance prefixes: (mode, mantissa).
    tolerances = [(160 - 20, 0), (160 - 7, 128), (160 + 2, 0), (243, 0), (246, 0)]
    for i, (name, data) in enumerate(sorted(raw.items())):
        with open(os.path.join(dirs["fuzz_whole"], name), "wb") as fh:
            fh.write(data)
        flags, sizes = chunkings[i % len(chunkings)]
        assert (flags & 7) + 1 == len(sizes)
        with open(os.path.join(dirs["fuzz_stream"], name), "wb") as fh:
            fh.write(bytes([flags] + sizes) + data)
        mode, mant = tolerances[i % len(tolerances)]
        with open(os.path.join(dirs["fuzz_tolerance"], name), "wb") as fh:
            fh.write(bytes([mode, mant]) + data)
    # Edit seeds: each base with a few hundred random edit bytes (fixed seed, so the corpus
    # is the same on every run).
    rng = random.Random(15)
    edit_bases = [bytes([0, 4, 3, 0]), bytes([0, 7, 5, 0x2D]), bytes([1]), bytes([2])]
    for name, data in sorted(raw.items()):
        if data and len(data) <= 8000 and not name.startswith("regress_") and name.endswith(".stl"):
            edit_bases.append(bytes([3 if len(edit_bases) % 2 else 7, len(data) & 0xFF, len(data) >> 8]) + data)
    for i, b in enumerate(edit_bases):
        with open(os.path.join(dirs["fuzz_edit"], "edit_%02d" % i), "wb") as fh:
            fh.write(b + bytes(rng.randrange(256) for _ in range(600)))
    for i, tokens in enumerate(NUMBER_SEEDS):
        with open(os.path.join(dirs["fuzz_number"], "numbers_%02d" % i), "w") as fh:
            fh.write(tokens)


# Number tokens for fuzz_number: the usual STL spellings, near-halfway cases of the fast
# path, long mantissas, exponent extremes, denormals, hex floats, inf/nan and malformed ones.
NUMBER_SEEDS = [
    "0 0 0 1 0 0 0 1 0",
    "3.99992108 -0.5 1.234567e+01 -1.0E-3 +2 7. .5 -0 0.0",
    "16777217 16777219 33554433 0.1 0.2 0.3 1e-7 3.4028235e38 1.17549435e-38",
    "2.0000001192092896 1.00000005960464477539 0.500000029802322387695 9007199254740993 1e22 1e23",
    "123456789012345678901234567890 0.000000000000000000000000000000001 1e-45 1.4e-45 7e-46",
    "3.4028236e38 3.40282357e38 1e39 1e999 -1e999 1e-999 0e999999 00000000000000000000001.5 1.5e0000000002",
    "0x1p3 0X1.8P-1 -0x.8p1 inf -INF nan NaN infinity 0x1p128",
    "1e 1e+ . - + .e1 1..2 1e1.5 --1",
    "4.2949673e9 -1.7976931348623157e308 2.2250738585072014e-308 4.9406564584124654e-324",
    "8.589973e9 0.30000001192092896 0.1000000014901161194 -1.0000000000000000000000000001",
]


if __name__ == "__main__":
    main()

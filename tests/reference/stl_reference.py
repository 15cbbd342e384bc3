#!/usr/bin/env python3
"""Independent reference implementation of `stltopo info --json`.

Written from the specification of the reader ("Core, part 1: read
every real-world STL file") and of the topology ("Core, part 2: half-edges, dual loops,
holes as faces"), NOT from the C++ sources, so that it is a genuine second
opinion. Standard library only; simple and slow on purpose (dicts, lists).

Usage: stl_reference.py FILE...   (one JSON object per line per file)
       stl_reference.py --self-check FILE...  (also checks the half-edge invariants)
       stl_reference.py [--shells] [--defects [--max-defects N]] FILE...
           (also the shell list and the defect lists of issue 16)

Exit status: 0 when every file was read, 1 when a file failed, 2 on usage errors.
"""

import json
import math
import re
import struct
import sys
from decimal import Decimal
from fractions import Fraction

MAX_TRIANGLES = 1 << 28
MAX_NAME_BYTES = 4096
MAX_NUMBER_CHARS = 4096


class StlError(Exception):
    def __init__(self, code, message, **loc):
        super().__init__(message)
        self.code = code
        self.message = message
        self.loc = loc  # offset / line / triangle


# ---------------------------------------------------------------------------
# float32 helpers

def _f32_bits(x):
    return struct.unpack('<I', struct.pack('<f', x))[0]


def _bits_f32(b):
    return struct.unpack('<f', struct.pack('<I', b))[0]


FLT_MAX = _bits_f32(0x7F7FFFFF)


def f32_round_exact(x):
    """Round an exact rational x to the nearest float32 (ties to even), as strtof does."""
    if x == 0:
        return 0.0
    sign = -1.0 if x < 0 else 1.0
    a = abs(x)
    # exponent e with 2^e <= a < 2^(e+1)
    e = a.numerator.bit_length() - a.denominator.bit_length()
    if Fraction(2) ** e > a:
        e -= 1
    elif Fraction(2) ** (e + 1) <= a:
        e += 1
    ulp_exp = max(e, -126) - 23
    q = a / (Fraction(2) ** ulp_exp)
    n = q.numerator // q.denominator
    rem = q - n
    if rem > Fraction(1, 2) or (rem == Fraction(1, 2) and n % 2 == 1):
        n += 1
    val = Fraction(n) * (Fraction(2) ** ulp_exp)
    if val > Fraction(FLT_MAX):
        return sign * math.inf
    return sign * float(val)


def f32_from_double(d):
    """float32 nearest to the double d (overflow gives inf)."""
    try:
        return struct.unpack('<f', struct.pack('<f', d))[0]
    except OverflowError:
        return math.copysign(math.inf, d)


_DEC_RE = re.compile(rb'[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z')
_HEX_RE = re.compile(rb'([+-]?)0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP]([+-]?[0-9]+))?\Z')
_INF_RE = re.compile(rb'[+-]?(?:inf|infinity)\Z', re.I)
_NAN_RE = re.compile(rb'[+-]?nan(?:\([0-9A-Za-z_]*\))?\Z', re.I)


def parse_number(tok):
    """Parse one whitespace-delimited token the way C-locale strtof would when it must
    consume the whole token. Returns a float holding an exact float32 value (or inf/nan),
    or None when the token is not a number."""
    if len(tok) > MAX_NUMBER_CHARS:
        return None
    if _DEC_RE.match(tok):
        d = float(tok)
        if math.isinf(d):
            return d
        f = f32_from_double(d)
        if f == d:
            return f
        if math.isinf(f) or abs(f) == FLT_MAX:
            return f32_round_exact(Fraction(Decimal(tok.decode('ascii'))))
        # The double d can only mislead when it sits exactly on a float32 midpoint
        # (double rounding). Then decide with the exact decimal value.
        b = _f32_bits(f)
        if (abs(d) > abs(f)):
            g = _bits_f32(b + 1)
        else:
            g = _bits_f32(b - 1) if (b & 0x7FFFFFFF) != 0 else -f
        if d == (f + g) / 2:
            return f32_round_exact(Fraction(Decimal(tok.decode('ascii'))))
        return f
    m = _HEX_RE.match(tok)
    if m:
        sign, mant, exp = m.groups()
        mant = mant.decode('ascii')
        if '.' in mant:
            ip, fp = mant.split('.')
        else:
            ip, fp = mant, ''
        digits = (ip + fp) or '0'
        val = Fraction(int(digits, 16), 16 ** len(fp))
        if exp:
            val *= Fraction(2) ** int(exp)
        r = f32_round_exact(val)
        if sign == b'-':
            r = -r if r != 0 else -0.0
        return r
    if _INF_RE.match(tok):
        return -math.inf if tok.startswith(b'-') else math.inf
    if _NAN_RE.match(tok):
        return math.nan
    return None


# ---------------------------------------------------------------------------
# Reading

class Raw:
    """What the readers produce before welding."""

    def __init__(self, fmt):
        self.format = fmt
        self.solids = []        # [name(str), triangle count]
        self.corners = []       # per triangle: ((x,y,z),(x,y,z),(x,y,z)) float32 values
        self.normals = []       # per triangle: (nx,ny,nz)
        self.attributes = []    # per triangle: uint16
        self.headers = []       # binary part headers (bytes)
        self.warnings = []      # [code, message]


def _decode_name(b):
    return b.decode('utf-8', errors='replace')


def _cap_name(raw, b):
    """Names longer than MAX_NAME_BYTES are cut (with a warning) at the last UTF-8
    character boundary that keeps at most MAX_NAME_BYTES bytes."""
    if len(b) > MAX_NAME_BYTES:
        cut = MAX_NAME_BYTES
        while cut > 0 and (b[cut] & 0xC0) == 0x80:  # b[cut] would start a continuation
            cut -= 1
        raw.warnings.append(['name-truncated',
                             'solid name of %d bytes cut to %d bytes' % (len(b), cut)])
        b = b[:cut]
    return _decode_name(b)


def _check_finite(tri_index, pts, **loc):
    for p in pts:
        for c in p:
            if not math.isfinite(c):
                raise StlError('non-finite', 'triangle %d has a non-finite coordinate' % tri_index,
                               triangle=tri_index, **loc)


def read_binary(data):
    raw = Raw('binary')
    size = len(data)
    off = 0
    first = True
    tri = 0
    rec = struct.Struct('<12fH')
    while True:
        rest = size - off
        if not first:
            if rest == 0:
                break
            if rest < 84:
                raw.warnings.append(['trailing-bytes',
                                     '%d trailing bytes after the last triangle at offset %d'
                                     % (rest, off)])
                break
        if rest < 84:
            raise StlError('truncated', 'binary header needs 84 bytes, %d present' % rest,
                           offset=size)
        header = data[off:off + 80]
        n = struct.unpack_from('<I', data, off + 80)[0]
        body = off + 84
        need = 50 * n
        have = size - body
        # Policy (the specification leaves the order open): a count the bytes cannot back is
        # `truncated`; `too-large` is for data that really holds more triangles than
        # the limit.
        if tri + min(n, have // 50) > MAX_TRIANGLES:
            raise StlError('too-large', 'more than %d triangles' % MAX_TRIANGLES,
                           offset=body + 50 * (MAX_TRIANGLES - tri))
        if have < need:
            raise StlError('truncated',
                           'header promises %d triangles (%d bytes) but %d bytes are present; '
                           'data stops at offset %d' % (n, need, have, size), offset=size)
        raw.headers.append(header)
        name = header.split(b'\0', 1)[0].strip()
        raw.solids.append([_cap_name(raw, name), n])
        for i, r in enumerate(rec.iter_unpack(data[body:body + need])):
            pts = ((r[3], r[4], r[5]), (r[6], r[7], r[8]), (r[9], r[10], r[11]))
            _check_finite(tri + i, pts, offset=body + 50 * i)
            raw.corners.append(pts)
            raw.normals.append((r[0], r[1], r[2]))
            raw.attributes.append(r[12])
        tri += n
        off = body + need
        first = False
    return raw


_TOKEN_RE = re.compile(rb'[^ \t\n\r\x0b\x0c]+')
_LINE_RE = re.compile(rb'\r\n|\r|\n')
_CONTROL_RE = re.compile(rb'[\x00-\x08\x0e-\x1f\x7f]')


def _begins_with_solid(data):
    d = data[3:] if data.startswith(b'\xef\xbb\xbf') else data
    d = d.lstrip(b' \t\n\r\x0b\x0c')
    return d[:5].lower() == b'solid'


def read_ascii(data):
    raw = Raw('ascii')
    if data.startswith(b'\xef\xbb\xbf'):
        data = data[3:]
    m = _CONTROL_RE.search(data)
    if m:
        # NUL and other control bytes never occur in ASCII STL (but do in binary data)
        line = data.count(b'\n', 0, m.start()) + 1
        raise StlError('ascii-syntax', 'line %d: control byte 0x%02x in ASCII STL'
                       % (line, m.group(0)[0]), line=line, offset=m.start())
    lines = _LINE_RE.split(data)
    # token stream: (token_lower_or_raw, line_no, line_bytes, end_pos_in_line)
    toks = []
    for ln, line in enumerate(lines, 1):
        for m in _TOKEN_RE.finditer(line):
            toks.append((m.group(0), ln, m.end()))
    nlines = len(lines)
    pos = 0
    ntok = len(toks)
    state = 'top'  # top | solid

    def syntax(msg, line):
        raise StlError('ascii-syntax', 'line %d: %s' % (line, msg), line=line)

    def need(what):
        nonlocal pos
        if pos >= ntok:
            raise StlError('unexpected-end', 'file ends inside a facet (expected %s)' % what,
                           line=nlines)
        t = toks[pos]
        pos += 1
        return t

    def skip_rest_of_line(line):
        nonlocal pos
        while pos < ntok and toks[pos][1] == line:
            pos += 1

    tri = 0
    while pos < ntok:
        tok, line, end = toks[pos]
        kw = tok.lower()
        pos += 1
        if state == 'top':
            if kw != b'solid':
                syntax("expected 'solid', found %r" % tok[:40].decode('latin-1'), line)
            name = lines[line - 1][end:].strip(b' \t\n\r\x0b\x0c')
            skip_rest_of_line(line)
            raw.solids.append([_cap_name(raw, name), 0])
            state = 'solid'
            continue
        # inside a solid
        if kw == b'endsolid':
            skip_rest_of_line(line)
            state = 'top'
            continue
        if kw != b'facet':
            syntax("expected 'facet' or 'endsolid', found %r" % tok[:40].decode('latin-1'), line)
        t = need("'normal' or 'outer'")
        nrm = [0.0, 0.0, 0.0]  # `facet` without `normal` is accepted: normal (0,0,0)
        if t[0].lower() == b'normal':
            for k in range(3):
                t = need('a number')
                v = parse_number(t[0])
                if v is None:
                    syntax('malformed number %r' % t[0][:40].decode('latin-1'), t[1])
                nrm[k] = v
            t = need("'outer'")
        if t[0].lower() != b'outer':
            syntax("expected 'outer loop'", t[1])
        t = need("'loop'")
        if t[0].lower() != b'loop':
            syntax("expected 'loop' after 'outer'", t[1])
        pts = []
        while True:
            t = need("'vertex' or 'endloop'")
            k = t[0].lower()
            if k == b'vertex':
                p = []
                for _ in range(3):
                    u = need('a number')
                    v = parse_number(u[0])
                    if v is None:
                        syntax('malformed number %r' % u[0][:40].decode('latin-1'), u[1])
                    p.append(v)
                pts.append(tuple(p))
                continue
            if k == b'endloop':
                if len(pts) != 3:
                    syntax('facet has %d vertices, expected 3' % len(pts), t[1])
                skip_rest_of_line(t[1])
                break
            syntax("expected 'vertex' or 'endloop'", t[1])
        t = need("'endfacet'")
        if t[0].lower() != b'endfacet':
            syntax("expected 'endfacet'", t[1])
        skip_rest_of_line(t[1])
        _check_finite(tri, pts, line=t[1])
        raw.corners.append(tuple(pts))
        raw.normals.append(tuple(nrm))
        raw.attributes.append(0)
        raw.solids[-1][1] += 1
        tri += 1
        if tri > MAX_TRIANGLES:
            raise StlError('too-large', 'more than %d triangles' % MAX_TRIANGLES, line=t[1])
    if state == 'solid':
        raw.warnings.append(['missing-endsolid', 'file ends without endsolid'])
    return raw


def read_stl(data):
    size = len(data)
    if size == 0:
        raise StlError('empty', 'file is empty (0 bytes)', offset=0)
    if size >= 84:
        n = struct.unpack_from('<I', data, 80)[0]
        if size == 84 + 50 * n:
            return read_binary(data)
    if _begins_with_solid(data):
        try:
            return read_ascii(data)
        except StlError as ascii_err:
            # A leading `solid` is never trusted: a binary file (e.g. with a few
            # trailing bytes, or a concatenation) may start with it too. When the
            # bytes are not text, the binary reading (or its error) is the answer;
            # otherwise binary is used only when it reads cleanly.
            if size >= 84:
                if _CONTROL_RE.search(data):
                    return read_binary(data)
                try:
                    return read_binary(data)
                except StlError:
                    pass
            raise ascii_err
    if size < 84:
        raise StlError('not-stl', 'neither binary STL (needs 84 bytes) nor ASCII STL', offset=0)
    return read_binary(data)


# ---------------------------------------------------------------------------
# Welded mesh and read-time figures

class Mesh:
    pass


def weld(raw):
    m = Mesh()
    m.format = raw.format
    index = {}
    pos = []
    tris = []
    for pts in raw.corners:
        t = []
        for p in pts:
            v = index.get(p)  # float keys: -0.0 == +0.0 and hash equal
            if v is None:
                v = len(pos)
                index[p] = v
                pos.append(p)
            t.append(v)
        tris.append(tuple(t))
    m.positions = pos
    m.triangles = tris
    m.corners = raw.corners
    m.solids = raw.solids
    m.warnings = raw.warnings
    m.degenerate = [len(set(t)) != 3 for t in tris]

    # colours
    if any(b'COLOR=' in h for h in raw.headers):
        m.colors = 'magics'
    elif any(a & 0x8000 for a in raw.attributes):
        m.colors = 'viscam'
    else:
        m.colors = 'none'

    mism = 0
    area = 0.0
    vol = 0.0
    for (a, b, c), n in zip(raw.corners, raw.normals):
        e1 = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
        e2 = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
        cr = (e1[1] * e2[2] - e1[2] * e2[1],
              e1[2] * e2[0] - e1[0] * e2[2],
              e1[0] * e2[1] - e1[1] * e2[0])
        if (n[0] != 0 or n[1] != 0 or n[2] != 0) and normal_against(n, a, b, c):
            mism += 1
        area += 0.5 * math.sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2])
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1])
                + a[1] * (b[2] * c[0] - b[0] * c[2])
                + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    m.normalMismatches = mism
    m.area = area
    m.volume = vol
    if pos:
        m.bbox = {'min': [min(p[k] for p in pos) for k in range(3)],
                  'max': [max(p[k] for p in pos) for k in range(3)]}
    else:
        m.bbox = None
    return m


# ---------------------------------------------------------------------------
# Topology

BOUNDARY, INTERIOR, INCONSISTENT, NONMANIFOLD = 'boundary', 'interior', 'inconsistent', 'nonmanifold'


class Topo:
    pass


def build_topology(mesh, self_check=False):
    tris = mesh.triangles
    T = len(tris)
    nd = [t for t in range(T) if not mesh.degenerate[t]]
    # sides: s = 3*t + i, u = tris[t][i] -> v = tris[t][(i+1)%3]
    side_order = [3 * t + i for t in nd for i in range(3)]

    def uv(s):
        t, i = divmod(s, 3)
        return tris[t][i], tris[t][(i + 1) % 3]

    edges = {}  # undirected key -> sides in file order (dict keeps first-met order)
    for s in side_order:
        u, v = uv(s)
        edges.setdefault((u, v) if u < v else (v, u), []).append(s)

    partner = {}
    kind_of_side = {}
    n_bnd = n_nm = n_inc = 0
    for key, sides in edges.items():
        first_dir = uv(sides[0])
        fwd = [s for s in sides if uv(s) == first_dir]
        bwd = [s for s in sides if uv(s) != first_dir]
        for a, b in zip(fwd, bwd):  # first unpaired with first unpaired, in file order
            partner[a] = b
            partner[b] = a
        if len(sides) == 1:
            k = BOUNDARY
            n_bnd += 1
        elif len(sides) == 2:
            k = INTERIOR if bwd else INCONSISTENT
            if k == INCONSISTENT:
                n_inc += 1
        else:
            k = NONMANIFOLD
            n_nm += 1
        for s in sides:
            kind_of_side[s] = k

    # half-edge numbering
    he = {}
    npairs = 0
    for s in side_order:
        p = partner.get(s)
        if p is not None and p < s:
            he[s] = he[p] + 1
        else:
            he[s] = 2 * npairs
            npairs += 1
    H = 2 * npairs
    vert = [None] * H
    nxt = [None] * H
    face = [None] * H
    side_of = {}  # half-edge id of a triangle side -> side
    for s in side_order:
        t, i = divmod(s, 3)
        e = he[s]
        side_of[e] = s
        vert[e] = tris[t][i]
        nxt[e] = he[3 * t + (i + 1) % 3]
        face[e] = t
        if s not in partner:
            vert[e ^ 1] = tris[t][(i + 1) % 3]

    def prev_side(s):
        t, i = divmod(s, 3)
        return 3 * t + (i + 2) % 3

    # boundary twins: fan rule
    boundary_twins = sorted(he[s] ^ 1 for s in side_order if s not in partner)
    for b in boundary_twins:
        s = side_of[b ^ 1]
        h = s
        steps = 0
        while True:
            p = prev_side(h)  # the side of h's triangle that enters u = org(s)
            if p not in partner:
                nxt[b] = he[p] ^ 1
                break
            h = partner[p]
            steps += 1
            if steps > len(side_order) + 1:
                raise RuntimeError('fan walk does not terminate')

    # loops, ordered by their lowest half-edge id
    loops = []
    seen = set()
    for b in boundary_twins:
        if b in seen:
            continue
        loop = []
        e = b
        while e not in seen:
            seen.add(e)
            loop.append(e)
            e = nxt[e]
        if e != b:
            raise RuntimeError('boundary next is not a permutation')
        loops.append(loop)
    holes = []
    seams = 0
    for h, loop in enumerate(loops):
        for e in loop:
            face[e] = T + h
        if all(kind_of_side[side_of[e ^ 1]] == BOUNDARY for e in loop):
            holes.append(len(loop))
        else:
            seams += 1

    # non-manifold vertices: more than one vnext cycle among outgoing half-edges
    cycles = {}
    visited = [False] * H
    for e0 in range(H):
        if visited[e0]:
            continue
        e = e0
        while not visited[e]:
            visited[e] = True
            e = nxt[e ^ 1]
            if vert[e] != vert[e0]:
                raise RuntimeError('vnext leaves its vertex')
        if e != e0:
            raise RuntimeError('vnext is not a permutation')
        cycles[vert[e0]] = cycles.get(vert[e0], 0) + 1
    n_nmv = sum(1 for c in cycles.values() if c > 1)

    if self_check:
        assert sorted(nxt) == list(range(H)), 'next is not a permutation'
        for e in range(H):
            assert vert[nxt[e]] == vert[e ^ 1], 'vert[next e] != vert[e^1] at %d' % e
            assert face[nxt[e]] == face[e], 'face not constant along next at %d' % e
        for t in nd:
            e = he[3 * t]
            assert nxt[nxt[nxt[e]]] == e

    # shells: union-find over non-degenerate triangles sharing any edge
    parent = {t: t for t in nd}

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for sides in edges.values():
        r0 = find(sides[0] // 3)
        for s in sides[1:]:
            r = find(s // 3)
            if r != r0:
                parent[r] = r0
    shells = len({find(t) for t in nd})

    used = {v for t in nd for v in tris[t]}
    F = len(nd)
    E = len(edges)
    chi = len(used) - E + F
    watertight = F > 0 and n_bnd == 0 and n_nm == 0 and n_inc == 0
    manifold = n_nm == 0 and n_nmv == 0
    if watertight and manifold:  # a pinched closed mesh (cubes touching at a corner) has no genus
        g2 = 2 * shells - chi
        genus = g2 // 2 if g2 % 2 == 0 else g2 / 2
    else:
        genus = None

    tp = Topo()
    tp.edges = E
    tp.boundaryEdges = n_bnd
    tp.nonManifoldEdges = n_nm
    tp.inconsistentEdges = n_inc
    tp.nonManifoldVertices = n_nmv
    tp.holes = len(holes)
    tp.seams = seams
    tp.holeSizes = holes
    tp.shells = shells
    tp.eulerCharacteristic = chi
    tp.genus = genus
    tp.watertight = watertight
    tp.manifold = manifold
    tp.usedVertices = len(used)
    tp.halfedges = H
    # kept for the shell list and the defect lists
    tp.edge_sides = edges
    tp.kind_of_side = kind_of_side
    tp.side_of = side_of
    tp.vert = vert
    tp.nxt = nxt
    tp.face = face
    tp.loops = loops
    tp.find = find
    tp.nd = nd
    return tp


# ---------------------------------------------------------------------------
# Shells and defects (issue 16 "Per-shell report and a list of every defect with its
# location"), from the issue's definitions.

def normal_against(n, a, b, c):
    """Whether the stored normal n points against the winding of (a, b, c):
    n . ((b - a) x (c - a)) < 0, exactly (the issue's predicates have no epsilon). A
    non-finite n has no exact sign: the product in double decides, as in stltopo."""
    if all(math.isfinite(x) for x in n):
        # float32 values times 2^149 are integers (and exact doubles: no product overflows)
        n, a, b, c = ([int(x * 2.0 ** 149) for x in p] for p in (n, a, b, c))
    e1 = [b[k] - a[k] for k in range(3)]
    e2 = [c[k] - a[k] for k in range(3)]
    return (n[0] * (e1[1] * e2[2] - e1[2] * e2[1]) + n[1] * (e1[2] * e2[0] - e1[0] * e2[2])
            + n[2] * (e1[0] * e2[1] - e1[1] * e2[0])) < 0


def exact_six_volume(triangles):
    """Six times the signed volume of the tetrahedra (origin, a, b, c), exactly, in units of
    2^-447: every float32 is an integer times 2^-149."""
    def whole(x):
        return int(Fraction(x) * (1 << 149))
    total = 0
    for a, b, c in triangles:
        a, b, c = [whole(x) for x in a], [whole(x) for x in b], [whole(x) for x in c]
        total += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
                  + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return total


def tri_figures(corners):
    """(area, signed volume) of one triangle, with the formulas of the whole report."""
    a, b, c = corners
    e1 = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    e2 = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
    cr = (e1[1] * e2[2] - e1[2] * e2[1],
          e1[2] * e2[0] - e1[0] * e2[2],
          e1[0] * e2[1] - e1[1] * e2[0])
    area = 0.5 * math.sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2])
    vol = (a[0] * (b[1] * c[2] - b[2] * c[1])
           + a[1] * (b[2] * c[0] - b[0] * c[2])
           + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    return area, vol


def box(points):
    return {'min': [min(p[k] for p in points) for k in range(3)],
            'max': [max(p[k] for p in points) for k in range(3)]}


def shell_of_triangles(tp):
    """triangle -> shell, shells numbered by their lowest triangle id."""
    ids = {}
    out = {}
    for t in tp.nd:  # ascending
        r = tp.find(t)
        if r not in ids:
            ids[r] = len(ids)
        out[t] = ids[r]
    return out


def loop_shells(tp, shell_of):
    # a boundary loop's half-edges are the twins of triangle sides
    return [shell_of[tp.face[loop[0] ^ 1]] for loop in tp.loops]


def vertex_cycles(tp, shell_of, T):
    """[(vertex, shell)] for every vnext cycle (a cycle's shell: that of a triangle it touches)."""
    seen = set()
    out = []
    for e0 in range(len(tp.vert)):
        if e0 in seen:
            continue
        e = e0
        shell = None
        while e not in seen:
            seen.add(e)
            f = tp.face[e] if tp.face[e] < T else tp.face[e ^ 1]
            shell = shell_of[f]
            e = tp.nxt[e ^ 1]
        out.append((tp.vert[e0], shell))
    return out


def shell_list(m, tp):
    T = len(m.triangles)
    shell_of = shell_of_triangles(tp)
    n = len(set(shell_of.values()))
    tris = [[] for _ in range(n)]
    for t in tp.nd:
        tris[shell_of[t]].append(t)
    edges = [dict(e=0, bnd=0, nm=0, inc=0) for _ in range(n)]
    for key, sides in tp.edge_sides.items():
        c = edges[shell_of[sides[0] // 3]]
        c['e'] += 1
        k = tp.kind_of_side[sides[0]]
        if k == BOUNDARY:
            c['bnd'] += 1
        elif k == NONMANIFOLD:
            c['nm'] += 1
        elif k == INCONSISTENT:
            c['inc'] += 1
    holes = [0] * n
    seams = [0] * n
    for loop, s in zip(tp.loops, loop_shells(tp, shell_of)):
        if all(tp.kind_of_side[tp.side_of[e ^ 1]] == BOUNDARY for e in loop):
            holes[s] += 1
        else:
            seams[s] += 1
    cycles = {}
    for v, s in vertex_cycles(tp, shell_of, T):
        cycles[(v, s)] = cycles.get((v, s), 0) + 1
    nmv = [0] * n
    for (v, s), k in cycles.items():
        if k > 1:
            nmv[s] += 1
    solid_of = []
    for i, (name, count) in enumerate(m.solids):
        solid_of += [i] * count
    out = []
    for s in range(n):
        verts = {v for t in tris[s] for v in m.triangles[t]}
        area = vol = 0.0
        for t in tris[s]:
            a, v = tri_figures(m.corners[t])
            area += a
            vol += v
        c = edges[s]
        V, E, F = len(verts), c['e'], len(tris[s])
        chi = V - E + F
        closed = c['bnd'] == 0 and c['nm'] == 0 and c['inc'] == 0
        manifold = c['nm'] == 0 and nmv[s] == 0
        if c['inc']:
            orient = 'inconsistent'
        elif c['bnd']:
            orient = 'open'
        else:
            # the sign of the volume itself, not of its rounded sum (a flat shell is flat)
            six = exact_six_volume(m.corners[t] for t in tris[s])
            orient = 'outward' if six > 0 else 'inward' if six < 0 else 'flat'
        solids = {solid_of[t] for t in tris[s]}
        out.append({
            'id': s, 'triangles': F, 'vertices': V, 'edges': E, 'boundaryEdges': c['bnd'],
            'nonManifoldEdges': c['nm'], 'inconsistentEdges': c['inc'], 'nonManifoldVertices': nmv[s],
            'holes': holes[s], 'seams': seams[s], 'eulerCharacteristic': chi,
            'genus': (2 - chi) / 2 if closed and manifold else None,
            'closed': closed, 'manifold': manifold, 'consistent': c['inc'] == 0,
            'orientation': orient, 'solid': solids.pop() if len(solids) == 1 else 'mixed',
            'bbox': box([p for t in tris[s] for p in m.corners[t]]),
            'area': area, 'volume': vol,
        })
    return out


def defect_lists(m, tp, max_n):
    T = len(m.triangles)
    pos = m.positions
    shell_of = shell_of_triangles(tp)
    lshell = loop_shells(tp, shell_of)
    holes, seams = [], []
    for h, loop in enumerate(tp.loops):
        cut = [e for e in loop if tp.kind_of_side[tp.side_of[e ^ 1]] != BOUNDARY]
        perim = 0.0
        for e in loop:
            a, c = pos[tp.vert[e]], pos[tp.vert[e ^ 1]]
            perim += math.sqrt((a[0] - c[0]) ** 2 + (a[1] - c[1]) ** 2 + (a[2] - c[2]) ** 2)
        item = {'id': h, 'edges': len(loop), 'perimeter': perim,
                'vertices': [tp.vert[e] for e in loop][:max_n],
                'bbox': box([pos[tp.vert[e]] for e in loop]), 'shell': lshell[h]}
        if cut:
            item['cutEdges'] = [[tp.vert[e], tp.vert[e ^ 1]] for e in cut][:max_n]
            seams.append(item)
        else:
            holes.append(item)
    nme, inc = [], []
    for key in sorted(tp.edge_sides):
        sides = tp.edge_sides[key]
        k = tp.kind_of_side[sides[0]]
        triangles = sorted(s // 3 for s in sides)
        if k == NONMANIFOLD:
            nme.append({'vertices': list(key), 'positions': [list(pos[key[0]]), list(pos[key[1]])],
                        'triangles': triangles})
        elif k == INCONSISTENT:
            inc.append({'vertices': list(key), 'triangles': triangles})
    cycles = {}
    for v, _ in vertex_cycles(tp, shell_of, T):
        cycles[v] = cycles.get(v, 0) + 1
    nmv = [{'vertex': v, 'position': list(pos[v]), 'cycles': k} for v, k in sorted(cycles.items()) if k > 1]
    deg = []
    for t, (a, b, c) in enumerate(m.triangles):
        if m.degenerate[t]:
            corners = [0, 1, 2] if a == b == c else [0, 1] if a == b else [1, 2] if b == c else [0, 2]
            deg.append({'triangle': t, 'corners': corners})

    def kind(items):
        return {'count': len(items), 'items': items[:max_n]}
    return {'holes': kind(holes), 'seams': kind(seams), 'nonManifoldEdges': kind(nme),
            'inconsistentEdges': kind(inc), 'nonManifoldVertices': kind(nmv),
            'degenerateTriangles': kind(deg)}


# ---------------------------------------------------------------------------

def geometry_checks(m):
    """Zero-area triangles and duplicate groups (README, "Geometry"), in exact integer
    arithmetic: every float32 coordinate times 2^149 is an integer."""
    scaled = {}

    def ipos(v):
        p = scaled.get(v)
        if p is None:
            p = tuple(int(x * 2.0 ** 149) for x in m.positions[v])  # exact: a power of two
            scaled[v] = p
        return p
    zero = []
    sets = {}
    for t, (a, b, c) in enumerate(m.triangles):
        if m.degenerate[t]:
            continue
        pa, pb, pc = ipos(a), ipos(b), ipos(c)
        u = [pb[k] - pa[k] for k in range(3)]
        w = [pc[k] - pa[k] for k in range(3)]
        if u[1] * w[2] == u[2] * w[1] and u[2] * w[0] == u[0] * w[2] and u[0] * w[1] == u[1] * w[0]:
            zero.append(t)
        sets.setdefault(frozenset((a, b, c)), []).append(t)
    groups = []
    for members in sorted((g for g in sets.values() if len(g) > 1), key=lambda g: g[0]):
        first = m.triangles[members[0]]
        rotations = {first, first[1:] + first[:1], first[2:] + first[:2]}
        same = all(m.triangles[t] in rotations for t in members)
        groups.append({'triangles': members,
                       'orientation': 'same' if same else 'opposite' if len(members) == 2 else 'mixed'})
    return zero, groups


def info(path, data, self_check=False, shells=False, defects=None):
    """defects: None, or the maximum number of items per kind."""
    raw = read_stl(data)
    m = weld(raw)
    tp = build_topology(m, self_check)
    zero, groups = geometry_checks(m)
    out = {
        'file': path,
        'format': m.format,
        'solids': [{'name': n, 'triangles': c} for n, c in m.solids],
        'triangles': len(m.triangles),
        'vertices': len(m.positions),
        'degenerateTriangles': sum(m.degenerate),
        'zeroAreaTriangles': len(zero),
        'duplicateTriangles': sum(len(g['triangles']) - 1 for g in groups),
        'colors': m.colors,
        'normalMismatches': m.normalMismatches,
        'bbox': m.bbox,
        'area': m.area,
        'volume': m.volume,
        'warnings': [{'code': c, 'message': msg} for c, msg in m.warnings],
    }
    for k in ('edges', 'boundaryEdges', 'nonManifoldEdges', 'inconsistentEdges',
              'nonManifoldVertices', 'holes', 'seams', 'holeSizes', 'shells',
              'eulerCharacteristic', 'genus', 'watertight', 'manifold'):
        out[k] = getattr(tp, k)
    for k in ('selfIntersections', 'intersectionKinds', 'intersectingTriangles', 'intersectionsComplete', 'solid'):
        out[k] = None  # only with --intersections, which the reference does not compute
    if shells:
        out['shellList'] = shell_list(m, tp)
    if defects is not None:
        out['defects'] = defect_lists(m, tp, defects)
        out['defects']['zeroAreaTriangles'] = {'count': len(zero), 'items': [{'triangle': t} for t in zero][:defects]}
        out['defects']['duplicateTriangles'] = {'count': len(groups), 'items': groups[:defects]}
        out['defects']['selfIntersections'] = None
    return out


def main(argv):
    self_check = False
    shells = False
    defects = None
    max_defects = 1000
    files = []
    args = iter(argv)
    for a in args:
        if a == '--self-check':
            self_check = True
        elif a == '--shells':
            shells = True
        elif a == '--defects':
            defects = True
        elif a == '--max-defects':
            max_defects = int(next(args))
        else:
            files.append(a)
    if not files:
        sys.stderr.write('usage: stl_reference.py [--self-check] [--shells] [--defects [--max-defects N]] FILE...\n')
        return 2
    out = sys.stdout
    status = 0
    for path in files:
        try:
            if path == '-':
                data = sys.stdin.buffer.read()
            else:
                with open(path, 'rb') as f:
                    data = f.read()
        except OSError as e:
            obj = {'file': path, 'error': {'code': 'io', 'message': str(e)}}
            status = 1
        else:
            try:
                obj = info(path, data, self_check, shells, max_defects if defects else None)
            except StlError as e:
                err = {'code': e.code, 'message': e.message}
                err.update(e.loc)
                obj = {'file': path, 'error': err}
                status = 1
        out.write(json.dumps(obj, ensure_ascii=False) + '\n')
        out.flush()
    return status


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')
    sys.exit(main(sys.argv[1:]))

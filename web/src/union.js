// planUnion() and unionShells(): the boolean union of the closed shells that overlap, through
// manifold-3d, which the caller passes in (an optional peer dependency: stltopo has no
// boolean engine and never imports it). README, "Overlapping shells: a boolean union".
//
// The groups are the connected parts of the relation "intersects" (the shells'
// intersectsShells of the exact intersection pass) among the mesh's shells, where a part has
// two shells or more; they are numbered by their lowest shell id. A group is united only when
// every shell in it is closed, manifold, outward and free of self-intersections: manifold-3d
// takes only oriented closed manifolds, and the union of a self-intersecting or inside-out
// shell is not the part it was meant to be. Every other group is listed with the reason.
import { invalid } from './errors.js';

const kInvalid = 0xffffffff;

// The shells with their intersection fields, the per-triangle shell, and the triangles on
// the welded vertices (positions stay the mesh's), of any Mesh.
async function geometryOf(mesh, fromIndexed, options) {
  if (!mesh || !mesh.positions || !mesh.triangles || typeof mesh.nTriangles !== 'number') {
    throw invalid('planUnion() and unionShells() need a Mesh (from loadStl or fromIndexed)');
  }
  let triangles = mesh.triangles;
  const weld = mesh.vertexWeld;
  const welded = weld && mesh.stats && mesh.stats.weldedVertices !== undefined;
  if (welded) triangles = triangles.map((v) => weld[v]);
  const shells = mesh.shells;
  const known = shells && mesh.triangleShell && shells.every((s) => Array.isArray(s.intersectsShells))
    && mesh.stats && mesh.stats.intersectionsComplete !== null && mesh.stats.intersectionsComplete !== undefined;
  if (known) {
    return { shells, triangleShell: mesh.triangleShell, triangles, complete: mesh.stats.intersectionsComplete };
  }
  // The exact pass on the mesh as it is (its vertex and triangle ids stay, as in findIntersections()).
  const m = await fromIndexed(mesh.positions, triangles, {
    weld: 'none', shells: true, intersections: true, maxPairs: options.maxPairs, signal: options.signal,
  });
  return { shells: m.shells, triangleShell: m.triangleShell, triangles, complete: m.stats.intersectionsComplete };
}

// Why shell s cannot go into a union, or null.
function unfit(s) {
  if (!s.closed) {
    const what = [];
    if (s.boundaryEdges) what.push(`${s.boundaryEdges} boundary edges`);
    if (s.nonManifoldEdges) what.push(`${s.nonManifoldEdges} non-manifold edges`);
    if (s.inconsistentEdges) what.push(`${s.inconsistentEdges} inconsistent edges`);
    return `shell ${s.id} is not closed (${what.join(', ')}): manifold-3d takes closed shells only; repair it first`;
  }
  if (!s.manifold) return `shell ${s.id} has ${s.nonManifoldVertices} non-manifold vertices: split them first (repair step split-nonmanifold)`;
  if (s.orientation !== 'outward') {
    return `shell ${s.id} is ${s.orientation === 'inward' ? 'inside out (inward)' : s.orientation}: orient it outward first (repair step orient)`;
  }
  if (s.selfIntersects) return `shell ${s.id} intersects itself: its union would not be the part it was meant to be`;
  return null;
}

/** The groups of overlapping shells (see the top of this file); plain data. */
function groupsOf(shells) {
  const n = shells.length;
  const parent = Array.from({ length: n }, (_, i) => i);
  const find = (x) => {
    while (parent[x] !== x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const s of shells) {
    for (const k of s.intersectsShells) {
      const a = find(s.id), b = find(k);
      if (a !== b) parent[Math.max(a, b)] = Math.min(a, b);
    }
  }
  const members = new Map();
  for (let i = 0; i < n; ++i) {
    const r = find(i);
    if (!members.has(r)) members.set(r, []);
    members.get(r).push(i);
  }
  const groups = [];
  for (const ids of members.values()) {
    if (ids.length < 2) continue;
    let triangles = 0, volume = 0, reason = null;
    for (const i of ids) {
      triangles += shells[i].triangles;
      volume += shells[i].volume;
      reason ??= unfit(shells[i]);
    }
    groups.push({ index: groups.length, shells: ids, triangles, volume, fit: reason === null, reason });
  }
  return groups;
}

function manifoldOf(options) {
  const wasm = options.manifold;
  if (!wasm || typeof wasm !== 'object') {
    throw invalid('unionShells() needs { manifold }: the manifold-3d module, e.g. '
      + "const manifold = await (await import('manifold-3d')).default(); manifold.setup();");
  }
  if (typeof wasm.Manifold !== 'function' && typeof wasm.setup === 'function') wasm.setup();
  if (typeof wasm.Manifold !== 'function' || typeof wasm.Mesh !== 'function') {
    throw invalid('options.manifold is not a manifold-3d module (it has no Manifold and Mesh)');
  }
  return wasm;
}

// The triangles of each shell, in file order, from one pass: those of shell s are
// list[offsets[s]] .. list[offsets[s + 1] - 1] (degenerate triangles have no shell).
function trianglesByShell(triangleShell, nShells) {
  const offsets = new Uint32Array(nShells + 1);
  for (const s of triangleShell) if (s < nShells) ++offsets[s + 1];
  for (let s = 0; s < nShells; ++s) offsets[s + 1] += offsets[s];
  const list = new Uint32Array(offsets[nShells]);
  const fill = offsets.slice(0, nShells);
  for (let t = 0; t < triangleShell.length; ++t) if (triangleShell[t] < nShells) list[fill[triangleShell[t]]++] = t;
  return { offsets, list };
}

// Positions and triangles of shell s (its triangles: byShell), its vertices numbered by
// first appearance.
function shellArrays(positions, triangles, byShell, s) {
  const vertexOf = new Map();
  const pos = [];
  const ts = byShell.list.subarray(byShell.offsets[s], byShell.offsets[s + 1]);
  const tri = new Uint32Array(3 * ts.length);
  let k = 0;
  for (const t of ts) {
    for (let c = 0; c < 3; ++c) {
      const v = triangles[3 * t + c];
      let w = vertexOf.get(v);
      if (w === undefined) {
        w = vertexOf.size;
        vertexOf.set(v, w);
        pos.push(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
      }
      tri[k++] = w;
    }
  }
  return { vertProperties: new Float32Array(pos), triVerts: tri };
}

// manifold-3d's union of the group's shells: { positions, triangles, volume } or { reason }.
function uniteGroup(wasm, mesh, geo, byShell, group) {
  const made = [];
  try {
    for (const id of group.shells) {
      const { vertProperties, triVerts } = shellArrays(mesh.positions, geo.triangles, byShell, id);
      const mm = new wasm.Mesh({ numProp: 3, vertProperties, triVerts });
      let m;
      try {
        m = new wasm.Manifold(mm);
      } catch (e) {
        return { reason: `manifold-3d rejected shell ${id}: ${e && (e.code || e.message) || e}` };
      }
      made.push(m);
      const st = m.status();
      if (st !== 'NoError') return { reason: `manifold-3d rejected shell ${id}: ${st}` };
    }
    const u = wasm.Manifold.union(made);
    made.push(u);
    const st = u.status();
    if (st !== 'NoError') return { reason: `manifold-3d's union failed: ${st}` };
    const out = u.getMesh();
    const np = out.numProp;
    const nv = out.vertProperties.length / np;
    const positions = new Float32Array(3 * nv);
    for (let v = 0; v < nv; ++v) {
      positions[3 * v] = out.vertProperties[np * v];
      positions[3 * v + 1] = out.vertProperties[np * v + 1];
      positions[3 * v + 2] = out.vertProperties[np * v + 2];
    }
    return { positions, triangles: Uint32Array.from(out.triVerts), volume: u.volume() };
  } finally {
    for (const m of made) m.delete();
  }
}

export function createUnion(fromIndexed) {
  /**
   * Which shells overlap, and which of those groups unionShells() can unite: changes nothing
   * and needs no manifold-3d. Options: { maxPairs, signal } for the intersection pass, when
   * the mesh was not loaded with { shells: true, intersections: true }.
   */
  async function planUnion(mesh, options = {}) {
    if (options === null || typeof options !== 'object') throw invalid('options must be an object');
    const geo = await geometryOf(mesh, fromIndexed, options);
    return { groups: groupsOf(geo.shells), complete: geo.complete };
  }

  /**
   * A new Mesh in which each chosen group of overlapping shells is replaced by manifold-3d's
   * union of its shells; every other triangle stays as it was, in file order, with its
   * attribute word or colour, and the union's triangles follow, group after group. The input
   * mesh is not changed. Options: { manifold (required), groups (indices into planUnion's
   * groups; default every group that fits), load (fromIndexed options for the result,
   * default { shells: true, intersections: true }), maxPairs, signal }.
   * Resolves to { mesh (null when no group was united), groups, complete }: each group as
   * planUnion() gives it, with `united` and, when united, `result: { triangles, vertices,
   * volume }` (manifold-3d's volume of the union) or the `reason` it was not.
   */
  async function unionShells(mesh, options = {}) {
    if (options === null || typeof options !== 'object') throw invalid('options must be an object');
    const wasm = manifoldOf(options);
    const geo = await geometryOf(mesh, fromIndexed, options);
    const groups = groupsOf(geo.shells);
    let chosen = null;
    if (options.groups !== undefined) {
      if (!Array.isArray(options.groups)) throw invalid('options.groups must be an array of group indices');
      chosen = new Set();
      for (const g of options.groups) {
        if (!Number.isInteger(g) || g < 0 || g >= groups.length) {
          throw invalid(`group ${g} does not exist (the mesh has ${groups.length} groups of overlapping shells)`);
        }
        chosen.add(g);
      }
    }
    const pieces = [];
    const shellOut = new Uint8Array(geo.shells.length); // 1: replaced by a union
    // One pass over the triangles for every shell a union takes (not one per shell).
    const byShell = groups.some((g) => g.fit && (!chosen || chosen.has(g.index)))
      ? trianglesByShell(geo.triangleShell, geo.shells.length) : null;
    for (const g of groups) {
      g.united = false;
      if (chosen && !chosen.has(g.index)) {
        g.reason ??= 'not chosen';
        continue;
      }
      if (!g.fit) continue;
      const r = uniteGroup(wasm, mesh, geo, byShell, g);
      if (r.reason) {
        g.fit = false;
        g.reason = r.reason;
        continue;
      }
      g.united = true;
      g.result = { triangles: r.triangles.length / 3, vertices: r.positions.length / 3, volume: r.volume };
      for (const id of g.shells) shellOut[id] = 1;
      pieces.push(r);
    }
    if (pieces.length === 0) return { mesh: null, groups, complete: geo.complete };

    // The kept triangles (file order; degenerate ones have no shell and stay), their vertices
    // numbered by first appearance, then each union's.
    const ts = geo.triangleShell;
    let nKept = 0;
    for (let t = 0; t < ts.length; ++t) if (ts[t] === kInvalid || !shellOut[ts[t]]) ++nKept;
    let nNew = 0, nNewV = 0;
    for (const p of pieces) nNew += p.triangles.length / 3, nNewV += p.positions.length / 3;
    const newId = new Uint32Array(mesh.nVertices).fill(kInvalid);
    const positions = new Float32Array(3 * (Math.min(mesh.nVertices, 3 * nKept) + nNewV));
    const triangles = new Uint32Array(3 * (nKept + nNew));
    const colored = mesh.colorConvention && mesh.colorConvention !== 'none' && mesh.colors && mesh.colorValid;
    const words = colored ? null : new Uint16Array(nKept + nNew);
    const colors = colored ? new Uint8Array(3 * (nKept + nNew)) : null;
    const colorValid = colored ? new Uint8Array(nKept + nNew) : null;
    let nv = 0, k = 0;
    for (let t = 0; t < ts.length; ++t) {
      if (ts[t] !== kInvalid && shellOut[ts[t]]) continue;
      for (let c = 0; c < 3; ++c) {
        const v = geo.triangles[3 * t + c];
        if (newId[v] === kInvalid) {
          newId[v] = nv;
          positions.set(mesh.positions.subarray(3 * v, 3 * v + 3), 3 * nv);
          ++nv;
        }
        triangles[3 * k + c] = newId[v];
      }
      if (colored) {
        colors.set(mesh.colors.subarray(3 * t, 3 * t + 3), 3 * k);
        colorValid[k] = mesh.colorValid[t];
      } else if (mesh.attributes) {
        words[k] = mesh.attributes[t];
      }
      ++k;
    }
    for (const p of pieces) {
      positions.set(p.positions, 3 * nv);
      for (let i = 0; i < p.triangles.length; ++i) triangles[3 * k + i] = p.triangles[i] + nv;
      nv += p.positions.length / 3;
      k += p.triangles.length / 3;
    }
    const load = options.load === undefined ? { shells: true, intersections: true } : options.load;
    if (load === null || typeof load !== 'object') throw invalid('options.load must be an object');
    const result = await fromIndexed(positions.subarray(0, 3 * nv), triangles, {
      ...load, ...(colored ? { colors, colorValid } : { attributes: words }),
    });
    return { mesh: result, groups, complete: geo.complete };
  }

  return { planUnion, unionShells };
}


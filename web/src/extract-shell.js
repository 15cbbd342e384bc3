// extractShell: one shell of a mesh loaded with { shells: true } as an indexed mesh of its
// own, in the same form as the C++ extractShell (include/stltopo/shells.h).
import { stlError } from './errors.js';

/**
 * The indexed mesh of shell `s`: its triangles in file order, its vertices compacted and
 * numbered by first appearance in corner order (as reading numbers them), the attribute
 * words, stored normals and colours of its triangles, and the solids it has triangles in.
 */
export function extractShell(mesh, s) {
  const ts = mesh.triangleShell;
  if (!ts) throw stlError('invalid-argument', 'extractShell needs a mesh loaded with { shells: true }');
  const nShells = mesh.shells.length;
  if (!Number.isInteger(s) || s < 0 || s >= nShells) {
    throw stlError('invalid-argument', `shell ${s} does not exist (the mesh has ${nShells})`);
  }
  const n = mesh.shells[s].triangles;
  const tri = mesh.triangles;
  const pos = mesh.positions;
  const newId = new Uint32Array(mesh.nVertices).fill(0xffffffff);
  const positions = new Float32Array(3 * mesh.shells[s].vertices + 3 * n); // trimmed below
  const triangles = new Uint32Array(3 * n);
  const attributes = new Uint16Array(n);
  const normals = mesh.normals ? new Float32Array(3 * n) : null;
  const colors = mesh.colors ? new Uint8Array(3 * n) : null;
  const colorValid = mesh.colorValid ? new Uint8Array(n) : null;
  const solids = [];
  let nv = 0;
  let k = 0;
  let solid = 0;
  let lastSolid = -1;
  for (let t = 0; t < mesh.nTriangles; ++t) {
    if (ts[t] !== s) continue;
    for (let c = 0; c < 3; ++c) {
      const v = tri[3 * t + c];
      if (newId[v] === 0xffffffff) {
        newId[v] = nv;
        positions[3 * nv] = pos[3 * v];
        positions[3 * nv + 1] = pos[3 * v + 1];
        positions[3 * nv + 2] = pos[3 * v + 2];
        ++nv;
      }
      triangles[3 * k + c] = newId[v];
    }
    attributes[k] = mesh.attributes[t];
    if (normals) normals.set(mesh.normals.subarray(3 * t, 3 * t + 3), 3 * k);
    if (colors) {
      colors.set(mesh.colors.subarray(3 * t, 3 * t + 3), 3 * k);
      colorValid[k] = mesh.colorValid[t];
    }
    while (solid < mesh.solids.length && t >= mesh.solids[solid].firstTriangle + mesh.solids[solid].triangleCount) ++solid;
    const inSolid = solid < mesh.solids.length && t >= mesh.solids[solid].firstTriangle ? solid : -1;
    if (inSolid >= 0) {
      if (inSolid !== lastSolid) solids.push({ name: mesh.solids[inSolid].name, firstTriangle: k, triangleCount: 0 });
      ++solids[solids.length - 1].triangleCount;
    }
    lastSolid = inSolid;
    ++k;
  }
  return {
    positions: positions.slice(0, 3 * nv),
    triangles,
    attributes,
    normals,
    colors,
    colorValid,
    colorConvention: mesh.colorConvention,
    solids,
  };
}

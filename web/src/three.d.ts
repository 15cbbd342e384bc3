// Types for 'stltopo/three' (three.js is a peer dependency).
import type { BufferGeometry, LineSegments, Material } from 'three';
import type { Mesh } from './index.js';

export interface ToBufferGeometryOptions {
  /** Per-face colours: a non-indexed geometry with a `color` attribute (when the mesh has colours). */
  colors?: boolean;
  /** Compute vertex normals (default true). Use a flatShading material for crisp STL facets. */
  normals?: boolean;
  /** RGB 0..255 for triangles without a colour (default [200, 200, 200]). */
  defaultColor?: [number, number, number];
}

/** An indexed BufferGeometry, or non-indexed with per-face colours. */
export declare function toBufferGeometry(mesh: Mesh, options?: ToBufferGeometryOptions): BufferGeometry;

export interface HoleLines extends LineSegments<BufferGeometry, Material> {
  userData: { halfedges: Uint32Array; loops: Uint32Array };
}
export interface ProblemLines extends LineSegments<BufferGeometry, Material> {
  userData: { halfedges: Uint32Array; kinds: Uint8Array };
}

/** The holes' edges (and with { seams: true } the seams') as one LineSegments. */
export declare function holesToLineSegments(
  mesh: Mesh,
  options?: { color?: number; seams?: boolean; seamColor?: number; material?: Material },
): HoleLines;

/** The non-manifold and inconsistent edges as one LineSegments with vertex colours. */
export declare function problemEdgesToLineSegments(
  mesh: Mesh,
  options?: { nonManifoldColor?: number; inconsistentColor?: number; material?: Material },
): ProblemLines;


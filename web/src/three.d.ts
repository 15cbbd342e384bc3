// Types for 'stltopo/three' (three.js is a peer dependency).
import type { BufferGeometry, LineSegments, Material } from 'three';
import type { Mesh, IndexedOptions } from './index.js';

export interface ToBufferGeometryOptions {
  /**
   * Per-face colours: a non-indexed geometry with a float `color` attribute (when the mesh has
   * colours): the sRGB colour bytes converted to three.js's working colour space (linear).
   */
  colors?: boolean;
  /** Compute vertex normals (default true). Use a flatShading material for crisp STL facets. */
  normals?: boolean;
  /** sRGB bytes 0..255 for triangles without a colour (default [200, 200, 200]). */
  defaultColor?: [number, number, number];
}

/** The 256 sRGB byte values in three.js's working colour space (what toBufferGeometry uses). */
export declare function srgbByteTable(): Float32Array;

/** An indexed BufferGeometry, or non-indexed with per-face colours. */
export declare function toBufferGeometry(mesh: Mesh, options?: ToBufferGeometryOptions): BufferGeometry;

export interface HoleLines extends LineSegments<BufferGeometry, Material> {
  userData: { halfedges: Uint32Array; loops: Uint32Array };
}
export interface ProblemLines extends LineSegments<BufferGeometry, Material> {
  userData: { halfedges: Uint32Array; kinds: Uint8Array };
}

/**
 * The holes' edges (and with { seams: true } the seams') as one LineSegments; a loop's colour
 * depends only on whether it is a hole or a seam. Reads only the loops (no half-edge array).
 */
export declare function holesToLineSegments(
  mesh: Mesh,
  options?: { color?: number; seams?: boolean; seamColor?: number; material?: Material },
): HoleLines;

/** The non-manifold and inconsistent edges as one LineSegments with vertex colours. */
export declare function problemEdgesToLineSegments(
  mesh: Mesh,
  options?: { nonManifoldColor?: number; inconsistentColor?: number; material?: Material },
): ProblemLines;


/**
 * A stltopo Mesh from a BufferGeometry, indexed or not (non-indexed geometry is welded
 * exactly); groups become solids named "material <materialIndex>". Options as fromIndexed's.
 */
export declare function fromBufferGeometry(geometry: BufferGeometry, options?: IndexedOptions): Promise<Mesh>;

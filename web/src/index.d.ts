// Types for 'stltopo' (browser and Node entries). See docs/JS-API.md.

/** ~0u: "none" in every index array. */
export declare const kInvalid: 4294967295;

/** Edge classes per half-edge pair k = e >> 1 (problems.pairKind). */
export declare const EdgeKind: Readonly<{ Interior: 0; Boundary: 1; Inconsistent: 2; NonManifold: 3 }>;

export type ErrorCode =
  | 'empty' | 'not-stl' | 'truncated' | 'unexpected-end' | 'ascii-syntax' | 'non-finite' | 'too-large'
  | 'out-of-memory' | 'invalid-argument' | 'aborted' | 'invalid' | 'invalid-index' | 'write-failed' | 'wasm-load' | 'edit-refused';
export type WarningCode = 'trailing-bytes' | 'missing-endsolid' | 'name-truncated';

/** Every failure of loadStl: the same codes and messages as the C++ core. */
export declare class StlError extends Error {
  constructor(code: ErrorCode, message: string, location?: { offset?: number; line?: number; triangle?: number });
  readonly name: 'StlError';
  /** Stable code, e.g. 'truncated'. */
  code: ErrorCode;
  /** Byte offset in the input, when it applies. */
  offset?: number;
  /** 1-based ASCII line, when it applies. */
  line?: number;
  /** Triangle index, when it applies. */
  triangle?: number;
}

export type StlInput = ArrayBuffer | ArrayBufferView | Blob | Response | ReadableStream<Uint8Array> | AsyncIterable<Uint8Array>;

export interface LoadOptions {
  /** Build the half-edge topology (default true). */
  topology?: boolean;
  /** 'exact' (default) or a tolerance weld for the topology only (positions are never moved). */
  weld?: 'exact' | { tolerance: number };
  /** More triangles give 'too-large' (default 2^28); an integer in [1, 2^32), as the CLIs' --max-triangles. */
  maxTriangles?: number;
  /** More input bytes give 'too-large' (default 0 = unlimited). */
  maxBytes?: number;
  /** Keep the stored facet normals in mesh.normals (default false). */
  normals?: boolean;
  /** Cancels the load; it rejects with StlError code 'aborted'. */
  signal?: AbortSignal;
  /**
   * Called while bytes arrive (at most every ~50 ms) and once at the end with
   * fraction 1. fraction is NaN while the total size is unknown (plain streams).
   */
  onProgress?: (fraction: number, bytesRead: number) => void;
  /**
   * Zero-copy: arrays are borrowed views into wasm memory; call mesh.dispose(). (When the heap
   * cannot hold halfedges.prev and face beside the rest, those two are derived in JS instead.)
   */
  view?: boolean;
  /** Parse in a Web Worker (worker_threads in Node); arrays are transferred. */
  worker?: boolean;
  /**
   * Also build mesh.triangleShell, mesh.shells and mesh.defects (the shell report and every
   * defect with its location; 4 more bytes per triangle). Default false.
   */
  shells?: boolean;
  /**
   * Also find the exact geometry (implies shells): mesh.intersections, the intersection keys
   * of mesh.stats (selfIntersections, intersectionKinds, intersectingTriangles,
   * intersectionsComplete, solid) and each shell's selfIntersects, intersectsShells, parent
   * and depth (README, "Geometry"). Default false.
   */
  intersections?: boolean;
  /** The intersection pass's work limit (--max-pairs), default 4000000. */
  maxPairs?: number;
  /**
   * Threads of the read, the topology and the exact geometry (README, "Threads in JS"): 1 is
   * the single-threaded module; more need SharedArrayBuffer (a cross-origin isolated page, or
   * Node) and use the threaded module, with the same results. 0: the machine's cores. Default:
   * in browsers navigator.hardwareConcurrency when the page is isolated, else 1; in Node 1.
   */
  threads?: number;
}

/** How a shell is wound: inconsistent edges, else boundary edges, else the exact sign of its volume (`flat` at exactly 0). */
export type Orientation = 'inconsistent' | 'open' | 'outward' | 'inward' | 'flat';

/** One shell's report: the fields of `stltopo info --json --shells` ("shellList"). */
export interface Shell {
  /** Its index: shells are numbered by their lowest triangle id. */
  id: number;
  triangles: number;
  /** Vertices its triangles use (a vertex where shells touch counts in each). */
  vertices: number;
  edges: number;
  boundaryEdges: number;
  nonManifoldEdges: number;
  inconsistentEdges: number;
  /** Vertices with more than one vnext cycle within this shell. */
  nonManifoldVertices: number;
  holes: number;
  seams: number;
  eulerCharacteristic: number;
  /** (2 - eulerCharacteristic) / 2 when closed and manifold, else null. */
  genus: number | null;
  /** No boundary, non-manifold or inconsistent edge. */
  closed: boolean;
  manifold: boolean;
  /** No inconsistent edge. */
  consistent: boolean;
  orientation: Orientation;
  /** The index of the solid holding all of its triangles, 'mixed', or null without solids. */
  solid: number | 'mixed' | null;
  bbox: { min: [number, number, number]; max: [number, number, number] };
  area: number;
  /** Signed volume (sum of the signed tetrahedra from the origin), float64. */
  volume: number;
  /** With { intersections: true }: two of its triangles intersect. */
  selfIntersects?: boolean;
  /** With { intersections: true }: the other shells it intersects. */
  intersectsShells?: number[];
  /** With { intersections: true }: the innermost closed shell around it (closed shells meeting no other), else null. */
  parent?: number | null;
  /** With { intersections: true }: the number of shells around it (0 at the top level), null when not nested. */
  depth?: number | null;
}

/** The kinds of defect, in the order of the report. */
export type DefectKind = 'holes' | 'seams' | 'nonManifoldEdges' | 'inconsistentEdges' | 'nonManifoldVertices' |
  'degenerateTriangles' | GeometryDefectKind;
/** The geometric kinds of defect, with { intersections: true }. */
export type GeometryDefectKind = 'zeroAreaTriangles' | 'duplicateTriangles' | 'selfIntersections';
/** The geometric kinds, in the order of the report. */
export declare const GEOMETRY_DEFECT_KINDS: readonly GeometryDefectKind[];

/** One defect as mesh.defect() gives it: the item shapes of `info --json --defects`. */
export type Defect =
  | { id: number; edges: number; perimeter: number; vertices: number[]; bbox: { min: number[]; max: number[] };
      shell: number; cutEdges?: [number, number][] }
  | { vertices: [number, number]; positions: [number[], number[]]; triangles: number[] }
  | { vertices: [number, number]; triangles: [number, number] }
  | { vertex: number; position: number[]; cycles: number }
  | { triangle: number; corners: number[] }
  | { triangle: number }
  | { triangles: number[]; orientation: 'same' | 'opposite' | 'mixed' }
  | { triangles: [number, number]; kind: 'crossing' | 'touching' | 'coplanar'; point: [number, number, number] };

/** The kinds of defect, in the order of the report. */
export declare const DEFECT_KINDS: readonly DefectKind[];

/** One shell as an indexed mesh of its own (extractShell). */
export interface IndexedShell {
  /** Its vertices, compacted and numbered by first appearance in corner order. */
  positions: Float32Array;
  triangles: Uint32Array;
  attributes: Uint16Array;
  normals: Float32Array | null;
  colors: Uint8Array | null;
  colorValid: Uint8Array | null;
  colorConvention: 'none' | 'viscam' | 'magics';
  /** The solids it has triangles in (names kept), firstTriangle/triangleCount in its own numbering. */
  solids: Solid[];
}

/**
 * Shell s of a mesh loaded with { shells: true } as an indexed mesh: its triangles in file
 * order, positions compacted, attribute words, normals and colours kept.
 */
export declare function extractShell(mesh: Mesh, s: number): IndexedShell;

export interface Solid {
  name: string;
  firstTriangle: number;
  triangleCount: number;
}

export interface Warning {
  code: WarningCode;
  message: string;
  offset?: number;
  line?: number;
  triangle?: number;
}

/**
 * A boundary loop of a Mesh or an EditableMesh (face id nTriangles + id, as halfedges.face
 * holds it): a hole, or a seam when it holds cut sides.
 */
export interface BoundaryLoop {
  /** Boundary-loop index h (holes and seams share the numbering). */
  id: number;
  /** Its face id, nTriangles + id. */
  face: number;
  /** Its half-edges in next order, starting at loopHalfedge[id]. */
  halfedges: Uint32Array;
  /** vertices[i] = org(halfedges[i]). */
  vertices: Uint32Array;
  edgeCount: number;
  perimeter: number;
}

/** The keys of `stltopo info --json` that every mesh has (minus "file"). */
export interface MeshStats {
  format: 'binary' | 'ascii';
  solids: { name: string; triangles: number }[];
  triangles: number;
  /** Vertex positions (welded exactly); the topology of a tolerance weld uses weldedVertices of them. */
  vertices: number;
  degenerateTriangles: number;
  /** Three distinct, exactly collinear corners (README, "Geometry"). */
  zeroAreaTriangles: number;
  /** Triangles that are not the lowest id of their duplicate group. */
  duplicateTriangles: number;
  colors: 'none' | 'viscam' | 'magics';
  /** Facets whose stored non-zero normal n points against their winding: n . ((b - a) x (c - a)) < 0, decided exactly. */
  normalMismatches: number;
  bbox: { min: [number, number, number]; max: [number, number, number] } | null;
  area: number;
  volume: number;
  warnings: Warning[];
}

/** The topology's counts (one list: include/stltopo/counts.h), in TopologyStats and RepairFigures. */
export interface TopologyCounts {
  // BEGIN counts: written by scripts/gen-api-docs.mjs from the count list (include/stltopo/counts.h)
  /** Undirected edges (an edge may hold several half-edge pairs when it is cut). */
  edges: number;
  /** Edges with one triangle side. */
  boundaryEdges: number;
  /** Edges with three or more triangle sides. */
  nonManifoldEdges: number;
  /** Edges whose two sides run the same way (a flipped face). */
  inconsistentEdges: number;
  /** Vertices whose outgoing half-edges form more than one fan. */
  nonManifoldVertices: number;
  /** Boundary loops without a cut side. */
  holes: number;
  /** Boundary loops that contain a cut (inconsistent or non-manifold) side. */
  seams: number;
  /** Shells: edge-connected components of the non-degenerate triangles. */
  shells: number;
  // END counts
}

/** The keys of `stltopo info --json` that a mesh with topology (the default) has besides. */
export interface TopologyStats extends TopologyCounts {
  holeSizes: number[];
  eulerCharacteristic: number;
  /** null unless the mesh is watertight and manifold. */
  genus: number | null;
  /** Only with a tolerance weld: the representatives the topology uses. */
  weldedVertices?: number;
  watertight: boolean;
  manifold: boolean;
  /** The exact geometry (README, "Geometry"): null unless loaded with { intersections: true }. */
  selfIntersections: number | null;
  intersectionKinds: { crossing: number; touching: number; coplanar: number } | null;
  intersectingTriangles: number | null;
  intersectionsComplete: boolean | null;
  solid: boolean | null;
}

/**
 * Exactly the keys and values of `stltopo info --json`, minus "file", typed by whether the
 * mesh has topology: Stats<true> has every topology key (mesh.stats.holes is a number),
 * Stats<false> none, Stats (topology known only at run time) may have them.
 */
export type Stats<T extends boolean = boolean> = [T] extends [true]
  ? MeshStats & TopologyStats
  : [T] extends [false]
    ? MeshStats
    : MeshStats & Partial<TopologyStats>;

export type ValidateResult = { ok: true } | { ok: false; code: string; message: string; element?: number };

/**
 * The type of a topology field of Mesh<T>: present for Mesh<true> (what loadStl gives by
 * default and with { topology: true }), null for Mesh<false> ({ topology: false }), either
 * for Mesh (options only known at run time).
 */
export type IfTopology<T extends boolean, X> = [T] extends [true] ? X : [T] extends [false] ? null : X | null;

/**
 * Half-edge navigation (libstl's names; docs/JS-API.md), the same on a Mesh with topology
 * and on an EditableMesh. Half-edges are ids: twin(e) = e ^ 1.
 */
export interface HalfedgeNavigation {
  sym(e: number): number;
  twin(e: number): number;
  org(e: number): number;
  dst(e: number): number;
  lFace(e: number): number;
  rFace(e: number): number;
  lNext(e: number): number;
  lPrev(e: number): number;
  vnext(e: number): number;
  oNext(e: number): number;
  oPrev(e: number): number;
  dNext(e: number): number;
  dPrev(e: number): number;
  rNext(e: number): number;
  rPrev(e: number): number;
  /** The half-edges of the face left of e (triangle or boundary loop), in next order. */
  faceHalfedges(e: number): IterableIterator<number>;
  /** The outgoing half-edges of org(e), following vnext. */
  outgoingHalfedges(e: number): IterableIterator<number>;
}

export declare class Mesh<T extends boolean = boolean> {
  private constructor();
  /** true for { view: true } meshes (borrowed wasm views; dispose() them). */
  readonly view: boolean;
  /** 'unknown' for meshes of fromIndexed(). */
  format: 'binary' | 'ascii' | 'unknown';
  nVertices: number;
  nTriangles: number;
  /** Half-edge count (2 per pair); 0 without topology. */
  nHalfedges: number;
  colorConvention: 'none' | 'viscam' | 'magics';
  solids: Solid[];
  warnings: Warning[];
  /** The threads the load ran on (1 in the single-threaded module; see LoadOptions.threads). */
  threads: number;
  /**
   * Boundary loops made only of boundary-edge sides. Built, with `seams`, on first read: a
   * triangle soup has a loop per triangle (some 300 bytes of JS heap each); `loops` holds them flat.
   */
  holes: BoundaryLoop[];
  /** Boundary loops that contain cut (inconsistent or non-manifold) sides. */
  seams: BoundaryLoop[];
  /** The report of each shell, with { shells: true }; else null. */
  shells: Shell[] | null;
  /** The number of defects of a kind; throws invalid-argument without { shells: true }. */
  defectCount(kind: DefectKind): number;
  /** Defect i of a kind (0 <= i < defectCount(kind)) as an object; lists are not cut. */
  defect(kind: DefectKind, i: number): Defect;
  /** The exact geometry of this mesh, whatever it was loaded with (runs in the full module). */
  findIntersections(options?: { maxPairs?: number; worker?: boolean; signal?: AbortSignal }): Promise<{
    stats: Pick<Stats<true>, 'zeroAreaTriangles' | 'duplicateTriangles' | 'selfIntersections' | 'intersectionKinds' |
      'intersectingTriangles' | 'intersectionsComplete' | 'solid'>;
    shells: Shell[];
    triangleShell: Uint32Array;
    intersections: NonNullable<Mesh['intersections']>;
  }>;
  // BEGIN arrays: written by scripts/gen-api-docs.mjs from the bindings' array table
  /** x,y,z of vertex v at 3v..3v+2. 3 per vertex. */
  positions: Float32Array;
  /** Vertex ids of corner c of triangle t at 3t+c. 3 per triangle. */
  triangles: Uint32Array;
  /** Binary attribute word per triangle (0 for ASCII). 1 per triangle. */
  attributes: Uint16Array;
  /** sRGB bytes per triangle when colorConvention !== 'none'. 3 per triangle; null when colorConvention is 'none'. */
  colors: Uint8Array | null;
  /** 1 per triangle that has a colour. 1 per triangle; null when colorConvention is 'none'. */
  colorValid: Uint8Array | null;
  /** Stored facet normals, with { normals: true }. 3 per triangle; null without { normals: true }. */
  normals: Float32Array | null;
  /** Half-edge arrays, length nHalfedges; twin(e) = e ^ 1. Null with topology: false. */
  halfedges: IfTopology<T, {
    /** Next half-edge around the same face. 1 per halfedge. */
    next: Uint32Array;
    /** Inverse of next. 1 per halfedge. */
    prev: Uint32Array;
    /** Origin vertex (org). 1 per halfedge. */
    vert: Uint32Array;
    /** Left face: the triangle id, or nTriangles + h for boundary loop h. 1 per halfedge. */
    face: Uint32Array;
  }>;
  /** Per triangle: half-edge of side corner0->corner1, kInvalid if degenerate. 1 per triangle; null with topology: false. */
  triangleHalfedge: IfTopology<T, Uint32Array>;
  /** Per vertex: an outgoing half-edge, kInvalid if unused. 1 per vertex; null with topology: false. */
  vertexHalfedge: IfTopology<T, Uint32Array>;
  /** Per boundary loop: its lowest-id half-edge. 1 per loop; null with topology: false. */
  loopHalfedge: IfTopology<T, Uint32Array>;
  /** Per vertex: the representative vertex the topology uses (identity for exact weld). 1 per vertex; null with topology: false. */
  vertexWeld: IfTopology<T, Uint32Array>;
  /** All boundary loops, flat. Null with topology: false. */
  loops: IfTopology<T, {
    /** Loop h is halfedges[offsets[h] .. offsets[h+1]). nLoops + 1. */
    offsets: Uint32Array;
    /** The half-edges of every loop in next order, starting at loopHalfedge[h]. 1 per loop entry. */
    halfedges: Uint32Array;
    /** 1 when the loop contains a cut (inconsistent or non-manifold) side. 1 per loop. */
    isSeam: Uint8Array;
    /** Sum of the loop's edge lengths. 1 per loop. */
    perimeter: Float64Array;
  }>;
  /** Per-element problems. Null with topology: false. */
  problems: IfTopology<T, {
    /** Per pair k = e >> 1: 0 interior, 1 boundary, 2 inconsistent, 3 non-manifold (EdgeKind). 1 per pair. */
    pairKind: Uint8Array;
    /** 1 when two corners of the triangle weld together. 1 per triangle. */
    triangleDegenerate: Uint8Array;
    /** 1 when the vertex's outgoing half-edges form more than one vnext cycle. 1 per vertex. */
    vertexNonManifold: Uint8Array;
  }>;
  /** Per triangle: its shell (numbered by lowest triangle id), kInvalid if degenerate. 1 per triangle; null without { shells: true }. */
  triangleShell: Uint32Array | null;
  /** Every defect with its location, as flat arrays (mesh.defect(kind, i) gives one as an object). Null without { shells: true }. */
  defects: {
    /** Non-manifold edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex. 2 per non-manifold edge. */
    nonManifoldEdgeVertices: Uint32Array;
    /** Non-manifold edge i's triangles are nonManifoldEdgeTriangles[offsets[i] .. offsets[i+1]). one more than the non-manifold edges. */
    nonManifoldEdgeOffsets: Uint32Array;
    /** Every triangle with a side on each non-manifold edge, ascending. 1 per edge entry. */
    nonManifoldEdgeTriangles: Uint32Array;
    /** Inconsistent edge i joins vertices [2i] < [2i+1]; ordered by (smaller, larger) vertex. 2 per inconsistent edge. */
    inconsistentEdgeVertices: Uint32Array;
    /** The two triangles of inconsistent edge i, [2i] < [2i+1]. 2 per inconsistent edge. */
    inconsistentEdgeTriangles: Uint32Array;
    /** The non-manifold vertices, ascending. 1 per non-manifold vertex. */
    nonManifoldVertices: Uint32Array;
    /** The number of vnext cycles of each (>= 2). 1 per non-manifold vertex. */
    nonManifoldVertexCycles: Uint32Array;
    /** The degenerate triangles, ascending. 1 per degenerate triangle. */
    degenerateTriangles: Uint32Array;
    /** Corners that weld: bit 0 corners 0,1; bit 1 corners 1,2; bit 2 corners 2,0 (7: all three). 1 per degenerate triangle. */
    degenerateCorners: Uint8Array;
    /** Per boundary loop h: its shell. 1 per loop. */
    loopShell: Uint32Array;
  } | null;
  /**  */
  intersections: {
    /** The zero-area triangles (three distinct, exactly collinear corners), ascending. 1 per zero-area triangle. */
    zeroAreaTriangles: Uint32Array;
    /** Duplicate group g is duplicateTriangles[offsets[g] .. offsets[g+1]). one more than the duplicate groups. */
    duplicateOffsets: Uint32Array;
    /** The members of every duplicate group, ascending; groups by lowest member. 1 per group entry. */
    duplicateTriangles: Uint32Array;
    /** Per group: 0 same, 1 opposite, 2 mixed (DuplicateOrientation). 1 per duplicate group. */
    duplicateOrientation: Uint8Array;
    /** Intersecting pair i is triangles [2i] < [2i+1]; ordered by (i, j). 2 per pair. */
    pairs: Uint32Array;
    /** Per pair: 0 crossing, 1 touching, 2 coplanar (IntersectionKind). 1 per pair. */
    kinds: Uint8Array;
    /** Per pair: x,y,z of one point of the intersection (float64, for framing a camera). 3 per pair. */
    points: Float64Array;
    /** Per triangle: 1 when it is in an intersecting pair. 1 per triangle. */
    triangleIntersects: Uint8Array;
  };
  /** fromIndexed(): per vertex of the input, its vertex in the mesh (kInvalid when no triangle uses it). 1 per input vertex; null for meshes of loadStl(). */
  inputVertexMap: Uint32Array | null;
  // END arrays
  stats: Stats<T>;

  /**
   * Checks every topology invariant. { ok: false, code: 'out-of-memory' } when its work arrays,
   * or the prev and face it needs in the wasm heap, did not fit there (a view or worker load of
   * a mesh too large for the heap to hold them: prev and face were then derived in JS).
   */
  validate(): ValidateResult;
  /** Frees the wasm memory of a { view: true } mesh; a no-op otherwise. */
  dispose(): void;
}
/** The half-edge navigation of a Mesh: HalfedgeNavigation. */
export interface Mesh<T extends boolean = boolean> extends HalfedgeNavigation {}

/** LoadOptions that build the topology (the default): the mesh's topology fields are set. */
export type WithTopology = LoadOptions & { topology?: true };
/** LoadOptions with { topology: false }: the mesh's topology fields are null. */
export type WithoutTopology = LoadOptions & { topology: false };

/** Reads an STL input into a welded mesh and its half-edge topology. Rejects with StlError. */
export declare function loadStl(input: StlInput, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStl(input: StlInput, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStl(input: StlInput, options?: LoadOptions): Promise<Mesh>;

/** Node only: streams a file from disk (rejects in browsers). */
export declare function loadStlFile(path: string | URL, options?: WithTopology): Promise<Mesh<true>>;
export declare function loadStlFile(path: string | URL, options: WithoutTopology): Promise<Mesh<false>>;
export declare function loadStlFile(path: string | URL, options?: LoadOptions): Promise<Mesh>;

export interface IndexedOptions extends Omit<LoadOptions, 'weld' | 'maxTriangles' | 'maxBytes' | 'onProgress'> {
  /**
   * 'exact' (default): equal positions are one vertex, as loadStl welds them (so renderer
   * seams close); inputVertexMap maps the caller's vertex ids to the mesh's. 'none': the
   * caller's vertices as they are. { tolerance }: 'exact', then the tolerance weld of loadStl.
   */
  weld?: 'exact' | 'none' | { tolerance: number };
  /** Per-triangle attribute words (decoded as a file's: bit 15 = a VisCAM colour). */
  attributes?: Uint16Array | ArrayLike<number>;
  /** Per-triangle sRGB bytes (3 per triangle): VisCAM colours; not together with attributes. */
  colors?: Uint8Array | ArrayLike<number>;
  /** Per triangle 0/1 (default: every triangle coloured); only with colors. */
  colorValid?: Uint8Array | ArrayLike<number>;
  /** Named stretches of triangles, in order and not overlapping; the rest become unnamed solids. */
  solids?: Array<{ name?: string; firstTriangle: number; triangleCount: number }>;
}

/**
 * A Mesh (the same object as loadStl's) from positions (x,y,z per vertex) and triangles (3
 * vertex ids each). Rejects with StlError: invalid-index (error.triangle), non-finite (the
 * vertex in the message), invalid-argument (lengths, solids), too-large, out-of-memory.
 */
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options?: IndexedOptions & { topology?: true },
): Promise<Mesh<true>>;
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options: IndexedOptions & { topology: false },
): Promise<Mesh<false>>;
export declare function fromIndexed(
  positions: Float32Array | ArrayLike<number>,
  triangles: Uint32Array | ArrayLike<number>,
  options?: IndexedOptions,
): Promise<Mesh>;

export interface WriteOptions {
  /** 'binary' (default) or 'ascii'. */
  format?: 'binary' | 'ascii';
  /**
   * Binary colours: 'as-mesh' (default: the mesh's convention and attribute words as they
   * are), or re-encoded as 'viscam' / 'magics' (5 bits per channel), or 'none' (zero words).
   */
  colors?: 'as-mesh' | 'none' | 'viscam' | 'magics';
  /** Every solid's name (default: each solid's own). Cut before bytes the format cannot carry. */
  name?: string;
  /** 'stored' (default): the stored normals when the mesh kept them; 'computed': from the winding. */
  normals?: 'stored' | 'computed';
  /** Largest chunk of writeStl() (default 1 MiB; toStl() in browsers 8 MiB; at least 16 KiB is used). */
  chunkBytes?: number;
  /** Write in a worker (meshes of stltopo/worker are always written in one). */
  worker?: boolean;
}

/** The STL file of a mesh, chunk by chunk (fits a ReadableStream or a Node stream). */
export declare function writeStl(mesh: Mesh, options?: WriteOptions): AsyncIterableIterator<Uint8Array>;

/** The STL file of a mesh: a Blob (type model/stl) in browsers, one Uint8Array in Node. */
export declare function toStl(mesh: Mesh, options?: WriteOptions): Promise<Blob | Uint8Array>;

export interface InitOptions {
  /** URL of stltopo-wasm.wasm (a string is resolved against the page; in Node also a path). */
  wasmUrl?: string | URL | null;
  /** The bytes of stltopo-wasm.wasm; wins over wasmUrl. */
  wasmBinary?: ArrayBuffer | Uint8Array | null;
  /** URL of the worker script (stltopo's dist/worker-thread.js, or your bundle of it). */
  workerUrl?: string | URL | null;
  /**
   * URL of stltopo-full.wasm, the module of shells and defects, fromIndexed(), writing and
   * EditableMesh, fetched on the first use of one of those (plain loads need only
   * stltopo-wasm.wasm).
   */
  fullWasmUrl?: string | URL | null;
  /** The bytes of stltopo-full.wasm; wins over fullWasmUrl. */
  fullWasmBinary?: ArrayBuffer | Uint8Array | null;
  /**
   * URL of the directory that serves the threaded modules (stltopo-wasm-mt.{js,wasm,worker.js}
   * and stltopo-full-mt.*), default next to the package's files. Bundles need it for threads.
   */
  threadsUrl?: string | URL | null;
}
/**
 * Where the wasm and the worker script come from, when the bundler or server does not serve
 * them next to the package's files. Call it before the first load; null restores a default.
 * Failing to fetch or compile the wasm, or to start the worker, rejects loads with
 * StlError 'wasm-load', whose message names the URL and what came back.
 */
export declare function init(options: InitOptions): void;

export type AttributeElement = 'vertex' | 'triangle' | 'edge';
/** a, b: the two values (components numbers each); t: b's weight. Return the new value, or null to refuse the edit. */
export type AttributeRuleFn = (a: Float64Array, b: Float64Array, t: number) => ArrayLike<number> | null | false;
export type AttributeRule = 'keepFirst' | 'average' | 'fail' | AttributeRuleFn;
export type AttributeValues = Uint8Array | Int8Array | Uint16Array | Int16Array | Uint32Array | Int32Array | Float32Array | Float64Array;

export interface IndexedMeshInput {
  positions: Float32Array;
  triangles: Uint32Array;
  attributes?: Uint16Array;
  colors?: Uint8Array;
  colorValid?: Uint8Array;
  colorConvention?: 'none' | 'viscam' | 'magics';
  normals?: Float32Array;
  solids?: { name: string; firstTriangle: number; triangleCount: number }[];
  format?: 'binary' | 'ascii' | 'unknown';
}

/** The repair steps, in the order they run (docs/REPAIR.md). */
export type RepairStep = 'duplicates' | 'zero-area' | 'stitch' | 'orient' | 'split-nonmanifold' | 'fill-holes' | 'small-shells';

/** planRepair() options; the defaults are REPAIR_DEFAULTS (and `stltopo repair`'s). */
export interface RepairOptions {
  /** Default ['duplicates', 'zero-area', 'stitch', 'orient', 'fill-holes']. */
  steps?: RepairStep[];
  /** duplicates: also remove groups whose members face both ways (zero-thickness walls). */
  removeWalls?: boolean;
  /** stitch: merge boundary vertices at most this far apart (0: exact T-junctions only). */
  stitchTolerance?: number;
  /** fill-holes: skip holes with more edges (default 1000), more area or a longer perimeter (0: no limit). */
  maxHoleEdges?: number;
  maxHoleArea?: number;
  maxHolePerimeter?: number;
  /** fill-holes: refine the patch to the surrounding edge length, and fair its new vertices. */
  fill?: Array<'refine' | 'fair'>;
  /** small-shells: remove shells with fewer triangles (default 10) or less |volume| (0: no limit). */
  minShellTriangles?: number;
  minShellVolume?: number;
  /** Run the exact intersection pass (default true): nesting for orient, what remains. */
  intersections?: boolean;
  maxPairs?: number;
  /** Items to leave out: their step and their index in that step's items of an earlier plan. */
  exclude?: Array<{ step: RepairStep; item: number }>;
}

/** The figures a plan predicts and a log reports. */
export interface RepairFigures extends TopologyCounts {
  triangles: number;
  vertices: number;
  degenerateTriangles: number;
  zeroAreaTriangles: number;
  duplicateTriangles: number;
  eulerCharacteristic: number;
  watertight: boolean;
  manifold: boolean;
  /** null without the intersection pass. */
  selfIntersections: number | null;
  solid: boolean | null;
}

/** One thing a step does (or would do). Ids: of the mesh as the step finds it. */
export interface RepairItem {
  action: string;
  skipped: boolean;
  reason?: string;
  triangles: Uint32Array;
  vertices: Uint32Array;
  loops: Uint32Array;
  bbox: { min: [number, number, number]; max: [number, number, number] };
  /** How far it moves geometry. */
  moved: number;
}

export interface RepairPlan {
  fingerprint: string;
  before: RepairFigures;
  steps: Array<{ step: RepairStep; note: string; done: number; skipped: number; items: RepairItem[]; after: RepairFigures }>;
  after: RepairFigures;
  /** What the steps leave (self-intersections), with advice. */
  remaining: string;
  /** The checked options the plan was made with (applyRepair uses them). */
  options: object;
}

export interface RepairStepLog {
  step: RepairStep;
  status: 'ok' | ErrorCode;
  message?: string;
  done: number;
  skipped: number;
  /** Ids before the step. */
  removedTriangles: Uint32Array;
  changedTriangles: Uint32Array;
  /** Added triangles take the last ids after the step. */
  addedTriangles: number;
  removedVertices: Uint32Array;
  changedVertices: Uint32Array;
  addedVertices: number;
  maxMoved: number;
  areaRemoved: number;
  areaAdded: number;
}

export interface RepairLog {
  before: RepairFigures;
  after: RepairFigures;
  steps: RepairStepLog[];
  /** `info --json` of the mesh before and after (fresh builds). */
  beforeReport: Record<string, unknown>;
  afterReport: Record<string, unknown>;
}

/** A repair plan for a Mesh or an EditableMesh (docs/REPAIR.md); changes nothing. */
export declare function planRepair(mesh: Mesh | EditableMesh, options?: RepairOptions): Promise<RepairPlan>;
export declare const REPAIR_STEPS: readonly RepairStep[];
export declare const REPAIR_DEFAULTS: Readonly<Required<Omit<RepairOptions, 'exclude'>>>;

/** A group of closed shells that overlap (planUnion(), unionShells()). */
export interface UnionGroup {
  /** Its index in planUnion()'s list: groups are numbered by their lowest shell id. */
  index: number;
  /** The shells in it (two or more), each intersecting another of the group. */
  shells: number[];
  triangles: number;
  /** The sum of the shells' signed volumes (what `info` reports for them). */
  volume: number;
  /** Every shell closed, manifold, outward and without self-intersections: manifold-3d can unite them. */
  fit: boolean;
  /** Why the group is not (or was not) united, else null. */
  reason: string | null;
  /** unionShells(): whether the group was replaced by its union. */
  united?: boolean;
  /** unionShells(), when united: manifold-3d's union, and its volume. */
  result?: { triangles: number; vertices: number; volume: number };
}

export interface UnionOptions {
  /** The manifold-3d module (its default export, awaited; setup() is called when needed). */
  manifold: unknown;
  /** The indices of the groups to unite (default: every group that fits). */
  groups?: number[];
  /** fromIndexed() options for the result (default { shells: true, intersections: true }). */
  load?: IndexedOptions;
  /** For the intersection pass of a mesh loaded without { shells: true, intersections: true }. */
  maxPairs?: number;
  signal?: AbortSignal;
}

/**
 * Which closed shells overlap, and which of those groups unionShells() can unite. Changes
 * nothing and needs no manifold-3d. A mesh loaded without { shells: true, intersections: true }
 * gets the intersection pass here.
 */
export declare function planUnion(mesh: Mesh, options?: { maxPairs?: number; signal?: AbortSignal }): Promise<{ groups: UnionGroup[]; complete: boolean }>;
/**
 * A new Mesh in which each chosen group of overlapping shells is manifold-3d's boolean union of
 * them; every other triangle stays, in file order, with its attribute word or colour, and the
 * unions' triangles follow. The input is not changed. `mesh` is null when no group was united.
 */
export declare function unionShells(mesh: Mesh, options: UnionOptions): Promise<{ mesh: Mesh | null; groups: UnionGroup[]; complete: boolean }>;

/** @deprecated An EditableMesh's loops are BoundaryLoops (face id nTriangles + id), as a Mesh's. */
export type EditableLoop = BoundaryLoop;

/**
 * Local edits on a copy of a mesh in wasm memory (docs/EDITING.md). Ids are slots: removed
 * elements leave dead slots until compact(). Arrays and stats are copies, made when read
 * after an edit. A refused edit throws StlError('edit-refused') and changes nothing.
 */
export declare class EditableMesh {
  /**
   * Resolves when the arrays are checked. Without a tolerance the editor is built at the
   * first call that reads or edits it; planRepair() then applyRepair() as the first calls
   * take the plan's repaired mesh without building the editor of the input.
   */
  static from(source: Mesh | IndexedMeshInput, options?: { tolerance?: number }): Promise<EditableMesh>;
  /**
   * The plan of EditableMesh.from(source).planRepair(options), made without building that
   * EditableMesh (what planRepair(mesh) does).
   */
  static planRepairOf(source: Mesh | IndexedMeshInput, options?: RepairOptions): Promise<RepairPlan>;
  readonly nVertices: number;
  readonly nTriangles: number;
  readonly nHalfedges: number;
  readonly nLiveTriangles: number;
  readonly nLiveVertices: number;
  readonly format: 'binary' | 'ascii' | 'unknown';
  readonly colorConvention: 'none' | 'viscam' | 'magics';
  readonly warnings: Warning[];
  readonly attributes: Uint16Array | null;
  readonly colors: Uint8Array | null;
  readonly colorValid: Uint8Array | null;
  readonly normals: Float32Array | null;
  // BEGIN editable arrays: written by scripts/gen-api-docs.mjs from the bindings' table
  /** x,y,z of vertex v at 3v..3v+2 (a dead vertex keeps its last position). 3 per vertex. */
  readonly positions: Float32Array;
  /** Vertex ids of corner c of triangle t at 3t+c; kInvalid for a dead triangle. 3 per triangle. */
  readonly triangles: Uint32Array;
  /** Half-edge arrays, length nHalfedges; twin(e) = e ^ 1. */
  readonly halfedges: {
    /** Next half-edge around the same face. 1 per halfedge. */
    readonly next: Uint32Array;
    /** Inverse of next. 1 per halfedge. */
    readonly prev: Uint32Array;
    /** Origin vertex (org). 1 per halfedge. */
    readonly vert: Uint32Array;
    /** Left face: the triangle id, or nTriangles + h for boundary loop h (as a Mesh). 1 per halfedge. */
    readonly face: Uint32Array;
  };
  /** Per triangle: half-edge of side corner0->corner1, kInvalid if degenerate or dead. 1 per triangle. */
  readonly triangleHalfedge: Uint32Array;
  /** Per vertex: an outgoing half-edge, kInvalid if unused. 1 per vertex. */
  readonly vertexHalfedge: Uint32Array;
  /** Per boundary loop: the twin of its earliest triangle side. 1 per loop. */
  readonly loopHalfedge: Uint32Array;
  /** All boundary loops, flat. */
  readonly loops: {
    /** Loop h is halfedges[offsets[h] .. offsets[h+1]). nLoops + 1. */
    readonly offsets: Uint32Array;
    /** The half-edges of every loop in next order, starting at loopHalfedge[h]. 1 per loop entry. */
    readonly halfedges: Uint32Array;
    /** 1 when the loop contains a cut (inconsistent or non-manifold) side. 1 per loop. */
    readonly isSeam: Uint8Array;
    /** Sum of the loop's edge lengths. 1 per loop. */
    readonly perimeter: Float64Array;
  };
  /** Per-element problems. */
  readonly problems: {
    /** Per pair k = e >> 1: 0 interior, 1 boundary, 2 inconsistent, 3 non-manifold (EdgeKind). 1 per pair. */
    readonly pairKind: Uint8Array;
    /** 1 when two corners of the triangle weld together. 1 per triangle. */
    readonly triangleDegenerate: Uint8Array;
    /** 1 when the vertex's outgoing half-edges form more than one vnext cycle. 1 per vertex. */
    readonly vertexNonManifold: Uint8Array;
  };
  // END editable arrays
  /** The figures of `info --json` for the compacted mesh: always with topology. */
  readonly stats: Stats<true>;
  readonly holes: BoundaryLoop[];
  readonly seams: BoundaryLoop[];
  triangleAlive(t: number): boolean;
  halfedgeAlive(e: number): boolean;
  validate(): ValidateResult;
  reserve(vertices: number, triangles: number): void;
  /** Moves vertex v: geometry only (triangles, topology, ids and attributes stay); the loops' perimeters follow. */
  setPosition(v: number, x: number, y: number, z: number): void;
  removeTriangle(t: number): void;
  addVertex(x: number, y: number, z: number): number;
  addTriangle(a: number, b: number, c: number, options?: { nonManifold?: boolean }): number;
  flipEdge(e: number): void;
  splitEdge(e: number, t?: number): number;
  collapseEdge(e: number, t?: number): number;
  /** Merges gone[i] into keep[i] for every i, in one edit (docs/EDITING.md). */
  mergeVertices(keep: number | ArrayLike<number>, gone: number | ArrayLike<number>, options?: { nonManifold?: boolean }): void;
  /** Closes a T-junction: splits boundary half-edge e's edge at the existing vertex v. */
  splitEdgeAt(e: number, v: number, options?: { nonManifold?: boolean }): void;
  /** splitEdgeAt for each (edges[i], vertices[i]), then mergeVertices(keep, gone), as one edit. */
  stitch(join: { keep?: ArrayLike<number>; gone?: ArrayLike<number>; edges?: ArrayLike<number>; vertices?: ArrayLike<number> },
    options?: { nonManifold?: boolean }): void;
  /** Splits vertex v into one vertex per fan: the new vertices' first id and count. */
  splitVertex(v: number): { first: number; count: number };
  reverseTriangle(t: number): void;
  reverseShell(t: number): void;
  fillHole(hole: number | BoundaryLoop, options?: { method?: 'fan' | 'ear' }): Uint32Array;
  compact(): { vertices: Uint32Array; triangles: Uint32Array; halfedges: Uint32Array };
  /** The STL file of the (compacted) mesh, whole. */
  toStl(options?: WriteOptions): Uint8Array;
  addAttribute(name: string, element: AttributeElement, values: AttributeValues,
    options?: { components?: number; merge?: AttributeRule; split?: AttributeRule }): void;
  attribute(name: string): AttributeValues | null;
  attributeNames(): string[];
  /** A repair plan for this mesh (docs/REPAIR.md); changes nothing. */
  planRepair(options?: RepairOptions): RepairPlan;
  /** Carries out a plan made for this mesh; returns the change log. */
  applyRepair(plan: RepairPlan): RepairLog;
  /** Undoes the last repair step still applied: its name, or null when there is none. */
  undo(): RepairStep | null;
  /** How many repair steps undo() can still take back. */
  readonly undoableSteps: number;
  dispose(): void;
}
/** The half-edge navigation of an EditableMesh: HalfedgeNavigation. */
export interface EditableMesh extends HalfedgeNavigation {}

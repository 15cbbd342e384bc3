// The three.js side of the demo: one conversion from the mesh arrays to a BufferGeometry, plus
// overlays for holes, seams and problem edges. Owns every GPU object it creates and disposes of
// them when the next mesh replaces the current one.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { LineSegments2 } from 'three/examples/jsm/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/examples/jsm/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/examples/jsm/lines/LineMaterial.js';
import { toBufferGeometry } from 'stltopo/three';

export const colors = {
  front: '#aab4c0',
  back: '#b3123f',
  seams: '#ff8a00',
  nonManifold: '#ff1f1f',
  inconsistent: '#ff2bd6',
  nonManifoldVertex: '#ffffff',
  inward: '#7b3fe4',
  intersecting: '#ffb300',
  highlight: '#ffffff',
  wire: '#1b222b',
};

// Hole colours: bright, cool and yellow hues that stay clear of the fixed colours above.
const holePalette = [
  '#00e5ff', '#76ff03', '#ffee00', '#2f7bff', '#00d97e', '#b388ff',
  '#ffc400', '#1de9b6', '#80d8ff', '#c6ff00', '#7c4dff', '#a7ffeb',
];
export const holeColor = (id) => holePalette[id % holePalette.length];

const kPairBoundary = 1;
const kPairInconsistent = 2;
const kPairNonManifold = 3;

/**
 * Converts the mesh arrays into a BufferGeometry (stltopo/three's toBufferGeometry: indexed and
 * sharing `mesh.positions` and `mesh.triangles`, or with per-face colours one triangle per three
 * corners, the sRGB colour bytes converted to linear; triangles without a valid colour get
 * `fallback`). Flat shading comes from the material, so no vertex normals.
 */
export function meshToGeometry(mesh, { useColors = true, fallback = colors.front } = {}) {
  const n = parseInt(fallback.slice(1), 16); // '#rrggbb'
  return toBufferGeometry(mesh, { colors: useColors, normals: false, defaultColor: [(n >> 16) & 255, (n >> 8) & 255, n & 255] });
}

const query = new URLSearchParams(globalThis.location?.search ?? '');

/** Meshes with more triangles are drawn coarser (Viewer.setMesh); ?previewTriangles=N sets it (the tests). */
export const PREVIEW_TRIANGLES = Number(query.get('previewTriangles')) || 2_000_000;

/**
 * Overlays past these sizes are drawn plainer, and the page says so (Viewer.plainer): a line
 * layer of more than FAT_LINE_SEGMENTS segments as 1-pixel lines rather than screen-wide ones,
 * and the holes without rings when more than MAX_RINGS are small. A screen-wide line is a quad
 * with its own shader work per pixel: in Chromium's software renderer (no GPU) one pass took
 * some 30 µs a segment a frame, so a triangle soup of 100k triangles (a hole a triangle, 300k
 * hole edges in two passes, 100k rings) took 21 s a frame. ?fatLines=N and ?rings=N set them
 * (the tests).
 */
export const FAT_LINE_SEGMENTS = Number(query.get('fatLines')) || 20_000;
export const MAX_RINGS = Number(query.get('rings')) || 2_000;
/** Whether the segments `xyz` (6 floats each) are drawn as 1-pixel lines. */
const isThin = (xyz) => xyz.length / 6 > FAT_LINE_SEGMENTS;

/** A geometry sharing `g`'s attributes that draws triangles 0, stride, 2·stride, … of it. */
function strided(g, stride) {
  const index = g.index.array;
  const n = Math.ceil(index.length / 3 / stride);
  const out = new Uint32Array(3 * n);
  for (let i = 0, t = 0; i < n; ++i, t += stride) out.set(index.subarray(3 * t, 3 * t + 3), 3 * i);
  const c = new THREE.BufferGeometry();
  for (const [name, attr] of Object.entries(g.attributes)) c.setAttribute(name, attr);
  c.setIndex(new THREE.BufferAttribute(out, 1));
  c.boundingBox = g.boundingBox;
  c.boundingSphere = g.boundingSphere;
  return c;
}

/** Segment list (6 floats per segment) along closed vertex loops, and a matching colour list. */
function loopSegments(mesh, loops, colorOf) {
  let nSegments = 0;
  for (const loop of loops) nSegments += loop.vertices.length;
  const xyz = new Float32Array(nSegments * 6);
  const rgb = new Float32Array(nSegments * 6);
  const p = mesh.positions;
  const color = new THREE.Color();
  let o = 0;
  for (const loop of loops) {
    color.set(colorOf(loop));
    const vs = loop.vertices;
    for (let j = 0; j < vs.length; j++) {
      putSegment(xyz, o, p, vs[j], vs[(j + 1) % vs.length]);
      for (let k = 0; k < 6; k += 3) {
        rgb[o + k] = color.r;
        rgb[o + k + 1] = color.g;
        rgb[o + k + 2] = color.b;
      }
      o += 6;
    }
  }
  return { xyz, rgb };
}

/** Writes the segment from vertex a to vertex b of positions `p` at xyz[o..o + 6). */
function putSegment(xyz, o, p, a, b) {
  xyz[o] = p[3 * a];
  xyz[o + 1] = p[3 * a + 1];
  xyz[o + 2] = p[3 * a + 2];
  xyz[o + 3] = p[3 * b];
  xyz[o + 4] = p[3 * b + 1];
  xyz[o + 5] = p[3 * b + 2];
}

/** Segments of the undirected edges whose pair kind is `kind` (one segment per half-edge pair). */
function pairSegments(mesh, kind) {
  const pairKind = mesh.problems?.pairKind;
  const vert = mesh.halfedges?.vert;
  if (!pairKind || !vert) return new Float32Array(0);
  let n = 0;
  for (let k = 0; k < pairKind.length; k++) if (pairKind[k] === kind) n++;
  const xyz = new Float32Array(n * 6);
  const p = mesh.positions;
  let o = 0;
  for (let k = 0; k < pairKind.length; k++) {
    if (pairKind[k] !== kind) continue;
    putSegment(xyz, o, p, vert[2 * k], vert[2 * k + 1]);
    o += 6;
  }
  return xyz;
}

/**
 * The centre (the mean of its vertices) and radius (the largest distance of a vertex from the
 * centre) of a vertex loop, into out[0..3] = x, y, z, radius: no object a loop (a triangle
 * soup has a hole a triangle).
 */
function loopCentre(mesh, vertices, out) {
  const p = mesh.positions;
  let cx = 0, cy = 0, cz = 0;
  for (const v of vertices) {
    cx += p[3 * v];
    cy += p[3 * v + 1];
    cz += p[3 * v + 2];
  }
  const n = Math.max(1, vertices.length);
  cx /= n;
  cy /= n;
  cz /= n;
  let radius = 0;
  for (const v of vertices) radius = Math.max(radius, Math.hypot(p[3 * v] - cx, p[3 * v + 1] - cy, p[3 * v + 2] - cz));
  out[0] = cx;
  out[1] = cy;
  out[2] = cz;
  out[3] = radius;
  return out;
}

/** Loop centre, radius and (Newell) normal of a vertex loop. */
export function loopFrame(mesh, vertices) {
  const p = mesh.positions;
  const [cx, cy, cz, radius] = loopCentre(mesh, vertices, new Float64Array(4));
  const normal = new THREE.Vector3();
  for (let j = 0; j < vertices.length; j++) {
    const a = vertices[j], b = vertices[(j + 1) % vertices.length];
    const ax = p[3 * a] - cx, ay = p[3 * a + 1] - cy, az = p[3 * a + 2] - cz;
    const bx = p[3 * b] - cx, by = p[3 * b + 1] - cy, bz = p[3 * b + 2] - cz;
    normal.x += (ay - by) * (az + bz);
    normal.y += (az - bz) * (ax + bx);
    normal.z += (ax - bx) * (ay + by);
  }
  return { centre: new THREE.Vector3(cx, cy, cz), radius, normal };
}

function circleSprite() {
  const size = 64;
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = size;
  const g = canvas.getContext('2d');
  g.lineWidth = 9;
  g.strokeStyle = '#000';
  g.beginPath();
  g.arc(size / 2, size / 2, size / 2 - 8, 0, 2 * Math.PI);
  g.stroke();
  g.lineWidth = 5;
  g.strokeStyle = '#fff';
  g.stroke();
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}

/** The 12 edges of an axis-aligned box { min, max } as segments (6 floats each). */
function boxSegments({ min, max }) {
  const corner = (i) => [i & 1 ? max[0] : min[0], i & 2 ? max[1] : min[1], i & 4 ? max[2] : min[2]];
  const out = [];
  for (const [a, b] of [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]]) {
    out.push(...corner(a), ...corner(b));
  }
  return out;
}

export class Viewer {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    // Checking shader logs is a synchronous round trip to the GPU process; with a big mesh still
    // being drawn (software GL) it would stall the page. Keep it for development only.
    this.renderer.debug.checkShaderErrors = import.meta.env?.DEV ?? false;
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1); // STL files are usually Z-up (3D printing, CAD)
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight('#ffffff', '#3a4250', 1.6));
    const headlight = new THREE.DirectionalLight('#ffffff', 1.8);
    headlight.position.set(0.4, 0.8, 1);
    this.camera.add(headlight); // light follows the view, so every side reads well

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.addEventListener('change', () => this.requestRender());

    this.model = new THREE.Group();
    this.scene.add(this.model);
    this.layers = {}; // name → Object3D, toggled by setLayerVisible
    this.visible = { wireframe: false, backFaces: true, holes: true, seams: true, nonManifold: true, inconsistent: true, nonManifoldVertices: true, inward: true, intersecting: true };
    this.isolated = null; // the shell shown on its own, or null
    this.sprite = circleSprite();
    this.backUniforms = { color: { value: new THREE.Color(colors.back) }, mix: { value: 1 } };
    this.animation = null;

    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    this.renderer.setAnimationLoop(() => this.frame());
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  requestRender() {
    this.dirty = true;
  }

  frame() {
    if (this.animation) {
      const a = this.animation;
      const s = Math.min(1, (performance.now() - a.start) / a.duration);
      const e = s * s * (3 - 2 * s);
      this.camera.position.lerpVectors(a.fromPos, a.toPos, e);
      this.controls.target.lerpVectors(a.fromTarget, a.toTarget, e);
      if (s >= 1) this.animation = null;
      this.dirty = true;
    }
    this.controls.update();
    if (!this.dirty) return;
    this.dirty = false;
    this.renderer.render(this.scene, this.camera);
  }

  /** Drops the current mesh and frees its GPU buffers (and wasm memory for borrowed views). */
  clear(next = null) {
    this.model.traverse((o) => {
      o.geometry?.dispose();
      if (o.material) for (const m of [].concat(o.material)) m.dispose();
    });
    this.model.clear();
    if (this.geometry && this.geometry !== this.drawGeometry) this.geometry.dispose(); // not in the scene
    this.geometry = null;
    this.drawGeometry = null;
    this.layers = {};
    this.plainer = [];
    if (this.mesh !== next) this.mesh?.dispose?.(); // the same mesh shown again (an edit) stays alive
    this.mesh = null;
    this.highlight = null;
    this.preview = null;
    this.previewFocus = null;
    this.surfaces = [];
    this.isolated = null;
    this.requestRender();
  }

  /** Shows a mesh from loadStl(); returns the number of milliseconds spent building the scene. */
  setMesh(mesh, { keepView = false } = {}) {
    const t0 = performance.now();
    this.clear(mesh);
    this.mesh = mesh;
    // A mesh over PREVIEW_TRIANGLES is drawn coarser: 1 triangle in `stride` (every
    // stride-th id), without per-face colours; load.js says so on the page. this.geometry
    // keeps every triangle (layers pick their triangles by id from it); only the surfaces and
    // the wireframe draw the coarse one.
    const stride = Math.max(1, Math.ceil(mesh.nTriangles / PREVIEW_TRIANGLES));
    this.stride = stride;
    const geometry = meshToGeometry(mesh, { useColors: stride === 1 });
    this.geometry = geometry;
    this.drawGeometry = stride === 1 ? geometry : strided(geometry, stride);
    // Front and back faces are two draws of the same geometry. The back faces get their own
    // colour (flipped faces, and the inside seen through a hole stand out) and a larger polygon
    // offset, so that where both meet at a silhouette the front face wins the depth tie.
    // Both are offset behind the lines, which lie exactly on mesh edges.
    const vertexColors = !!geometry.getAttribute('color');
    const surface = (side, offset) => {
      const material = new THREE.MeshStandardMaterial({
        flatShading: true, roughness: 0.75, metalness: 0.05, side, vertexColors,
        color: vertexColors ? '#ffffff' : colors.front,
        polygonOffset: true, polygonOffsetFactor: offset, polygonOffsetUnits: offset,
      });
      if (side === THREE.BackSide) {
        material.onBeforeCompile = (shader) => {
          shader.uniforms.backColor = this.backUniforms.color;
          shader.uniforms.backMix = this.backUniforms.mix;
          shader.fragmentShader = 'uniform vec3 backColor;\nuniform float backMix;\n' + shader.fragmentShader.replace(
            '#include <color_fragment>',
            '#include <color_fragment>\n\tdiffuseColor.rgb = mix( diffuseColor.rgb, backColor, backMix );');
        };
        material.customProgramCacheKey = () => 'stltopo-back-faces';
      }
      return new THREE.Mesh(this.drawGeometry, material);
    };
    this.surfaces = [surface(THREE.FrontSide, 1), surface(THREE.BackSide, 4)];
    this.model.add(...this.surfaces);
    this.surface = surface;

    // Inward shells (closed, volume < 0): their front faces drawn again in their own colour,
    // in front of the surface.
    const inward = (mesh.shells ?? []).filter((s) => s.orientation === 'inward').map((s) => s.id);
    if (inward.length) {
      const sub = this.shellGeometry(new Set(inward));
      const m = new THREE.Mesh(sub, new THREE.MeshStandardMaterial({
        flatShading: true, roughness: 0.75, metalness: 0.05, color: colors.inward,
        polygonOffset: true, polygonOffsetFactor: 0.5, polygonOffsetUnits: 0.5,
      }));
      this.layers.inward = m;
      this.model.add(m);
    }

    // Self-intersecting triangles (loads with { intersections: true }): drawn again in their
    // own colour, in front of the surface.
    const hit = mesh.intersections?.triangleIntersects;
    if (hit && mesh.intersections.kinds.length) {
      const index = this.geometry.index?.array;
      const out = [];
      for (let t = 0; t < hit.length; t++) {
        if (!hit[t]) continue;
        if (index) out.push(index[3 * t], index[3 * t + 1], index[3 * t + 2]);
        else out.push(3 * t, 3 * t + 1, 3 * t + 2);
      }
      const sub = new THREE.BufferGeometry();
      for (const [name, attr] of Object.entries(this.geometry.attributes)) sub.setAttribute(name, attr);
      sub.setIndex(out);
      const m = new THREE.Mesh(sub, new THREE.MeshStandardMaterial({
        flatShading: true, roughness: 0.75, metalness: 0.05, color: colors.intersecting, side: THREE.DoubleSide,
        polygonOffset: true, polygonOffsetFactor: -0.5, polygonOffsetUnits: -0.5,
      }));
      this.layers.intersecting = m;
      this.model.add(m);
    }

    const diag = geometry.boundingSphere.radius * 2 || 1;
    this.diag = diag;
    const holes = mesh.holes ?? [];
    const seams = mesh.seams ?? [];

    // Holes: a bold pass that the surface can hide, over a faint pass that shows through it,
    // so a hole on the far side is still seen, and rings on small holes.
    if (holes.length) {
      const { xyz, rgb } = loopSegments(mesh, holes, (h) => holeColor(h.id));
      const group = new THREE.Group();
      const g = this.lineGeometry(xyz, rgb);
      group.add(this.linesOf(g, { width: 2.5, opacity: 0.45, depthTest: false, order: 10 }));
      group.add(this.linesOf(g, { width: 5, order: 11 }));
      this.notePlainLines(xyz, 'hole edges');
      const c = new Float64Array(4);
      const centres = [], ringColors = [];
      let nSmall = 0;
      for (const h of holes) {
        if (!(loopCentre(mesh, h.vertices, c)[3] < diag * 0.04)) continue; // small ones only (a NaN radius is not small)
        if (++nSmall > MAX_RINGS) continue;
        centres.push(c[0], c[1], c[2]);
        ringColors.push(holeColor(h.id));
      }
      if (nSmall > MAX_RINGS) {
        this.plainer.push(`no rings on the ${nSmall.toLocaleString('en-US')} small holes`);
      } else if (nSmall) {
        group.add(this.rings(centres, ringColors));
      }
      this.model.add(group);
      this.layers.holes = group;
    }
    if (seams.length) {
      const { xyz, rgb } = loopSegments(mesh, seams, () => colors.seams);
      this.layers.seams = this.lines(xyz, rgb, { width: 3, order: 13, depthTest: false, opacity: 0.9 });
      this.notePlainLines(xyz, 'seam edges');
      this.model.add(this.layers.seams);
    }
    for (const [name, kind, width] of [['inconsistent', kPairInconsistent, 4], ['nonManifold', kPairNonManifold, 4.5]]) {
      const xyz = pairSegments(mesh, kind);
      if (!xyz.length) continue;
      const c = new THREE.Color(colors[name]);
      const rgb = new Float32Array(xyz.length);
      for (let i = 0; i < rgb.length; i += 3) rgb.set([c.r, c.g, c.b], i);
      this.layers[name] = this.lines(xyz, rgb, { width, order: 14, depthTest: false });
      this.notePlainLines(xyz, name === 'inconsistent' ? 'inconsistent edges' : 'non-manifold edges');
      // Problem edges are often tiny next to the model: ring each one (when there are few).
      if (xyz.length / 6 <= 500) {
        const mids = [];
        for (let i = 0; i < xyz.length; i += 6) {
          mids.push((xyz[i] + xyz[i + 3]) / 2, (xyz[i + 1] + xyz[i + 4]) / 2, (xyz[i + 2] + xyz[i + 5]) / 2);
        }
        const group = new THREE.Group();
        group.add(this.layers[name], this.rings(mids, colors[name]));
        this.layers[name] = group;
      }
      this.model.add(this.layers[name]);
    }
    const vnm = mesh.problems?.vertexNonManifold;
    if (vnm) {
      const pts = [];
      for (let v = 0; v < vnm.length; v++) {
        if (vnm[v]) pts.push(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
      }
      if (pts.length) {
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
        const points = new THREE.Points(g, new THREE.PointsMaterial({
          size: 11, sizeAttenuation: false, color: colors.nonManifoldVertex, depthTest: false,
        }));
        points.renderOrder = 15;
        this.layers.nonManifoldVertices = points;
        this.model.add(points);
      }
    }
    this.applyVisibility();
    if (!keepView) this.frameAll(false);
    this.requestRender();
    return performance.now() - t0;
  }

  /** The triangle under the client point (x, y), or null (edit mode's click). */
  pick(clientX, clientY) {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    const hit = ray.intersectObjects(this.model.children.filter((o) => o.isMesh), false)[0];
    if (!hit) return null;
    return hit.object.geometry === this.drawGeometry ? hit.faceIndex * this.stride : hit.faceIndex;
  }

  /** Screen-sized rings (always on top) at `xyz` (3 floats each), one colour or one per ring. */
  rings(xyz, color) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(xyz, 3));
    const rgb = [];
    const c = new THREE.Color();
    for (let i = 0; i < xyz.length / 3; i++) rgb.push(...c.set(Array.isArray(color) ? color[i] : color).toArray());
    g.setAttribute('color', new THREE.Float32BufferAttribute(rgb, 3));
    const points = new THREE.Points(g, new THREE.PointsMaterial({
      size: 26, sizeAttenuation: false, map: this.sprite, vertexColors: true,
      transparent: true, depthTest: false, depthWrite: false, alphaTest: 0.2,
    }));
    points.renderOrder = 12;
    return points;
  }

  /** What the line layer of segments `xyz` gives up (FAT_LINE_SEGMENTS), for the page's note. */
  notePlainLines(xyz, what) {
    if (isThin(xyz)) this.plainer.push(`the ${(xyz.length / 6).toLocaleString('en-US')} ${what} as 1-pixel lines`);
  }

  /**
   * The geometry of line segments (6 floats each in `xyz`, a colour per end in `rgb`):
   * screen-wide lines', or past FAT_LINE_SEGMENTS of them 1-pixel lines'. Passes over the same
   * segments (the holes') share one: one upload.
   */
  lineGeometry(xyz, rgb) {
    if (isThin(xyz)) {
      const f32 = (a) => (a instanceof Float32Array ? a : new Float32Array(a));
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(f32(xyz), 3));
      g.setAttribute('color', new THREE.BufferAttribute(f32(rgb), 3));
      return g;
    }
    const g = new LineSegmentsGeometry();
    g.setPositions(xyz);
    g.setColors(rgb);
    return g;
  }

  /** Line segments `width` pixels wide (1 pixel when thin; see lineGeometry). */
  lines(xyz, rgb, options) {
    return this.linesOf(this.lineGeometry(xyz, rgb), options);
  }

  /** A pass over the segments of a lineGeometry(). */
  linesOf(g, { width, opacity = 1, depthTest = true, order = 10 }) {
    const lines = g.isLineSegmentsGeometry
      ? new LineSegments2(g, new LineMaterial({
        linewidth: width, vertexColors: true, depthTest, depthWrite: false,
        transparent: opacity < 1, opacity, worldUnits: false,
      }))
      : new THREE.LineSegments(g, new THREE.LineBasicMaterial({
        vertexColors: true, depthTest, depthWrite: false, transparent: opacity < 1, opacity,
      }));
    lines.renderOrder = order;
    lines.frustumCulled = false;
    return lines;
  }

  setVisible(name, on) {
    this.visible[name] = on;
    this.applyVisibility();
  }

  applyVisibility() {
    const v = this.visible;
    for (const name of ['holes', 'seams', 'nonManifold', 'inconsistent', 'nonManifoldVertices', 'inward', 'intersecting']) {
      if (this.layers[name]) this.layers[name].visible = v[name];
    }
    this.backUniforms.mix.value = v.backFaces ? 1 : 0;
    if (v.wireframe && !this.layers.wireframe && this.geometry) {
      const wire = new THREE.Mesh(this.drawGeometry, new THREE.MeshBasicMaterial({
        color: colors.wire, wireframe: true, transparent: true, opacity: 0.35, depthWrite: false,
      }));
      wire.renderOrder = 5;
      this.layers.wireframe = wire;
      this.model.add(wire);
    }
    if (this.layers.wireframe) this.layers.wireframe.visible = v.wireframe;
    this.requestRender();
  }

  /** Moves the camera to look at `centre` from direction `dir` at a distance showing `radius`. */
  lookAt(centre, radius, dir, animate = true) {
    const fov = THREE.MathUtils.degToRad(this.camera.fov);
    const fit = radius / Math.sin(Math.min(fov, fov * this.camera.aspect) / 2);
    const toPos = centre.clone().add(dir.clone().normalize().multiplyScalar(fit * 1.08));
    const sceneRadius = this.geometry?.boundingSphere.radius || radius;
    this.camera.near = Math.max(sceneRadius, radius) / 2000;
    this.camera.far = (fit + sceneRadius * 4) * 4;
    this.camera.updateProjectionMatrix();
    if (animate) {
      this.animation = {
        start: performance.now(), duration: 450,
        fromPos: this.camera.position.clone(), toPos,
        fromTarget: this.controls.target.clone(), toTarget: centre.clone(),
      };
    } else {
      this.animation = null;
      this.camera.position.copy(toPos);
      this.controls.target.copy(centre);
    }
    this.requestRender();
  }

  /** A geometry of the triangles of the shells in `ids` (a Set), sharing the main geometry's attributes. */
  shellGeometry(ids) {
    const ts = this.mesh.triangleShell;
    const g = new THREE.BufferGeometry();
    for (const [name, attr] of Object.entries(this.geometry.attributes)) g.setAttribute(name, attr);
    const index = this.geometry.index?.array;
    const out = [];
    for (let t = 0; t < ts.length; t += this.stride) { // every triangle, or the coarse view's
      if (!ids.has(ts[t])) continue;
      if (index) out.push(index[3 * t], index[3 * t + 1], index[3 * t + 2]);
      else out.push(3 * t, 3 * t + 1, 3 * t + 2);
    }
    g.setIndex(out);
    return g;
  }

  /** Shows only shell `id` (null: all of them again) and frames it. */
  isolateShell(id) {
    if (this.isolated) {
      this.model.remove(this.isolated);
      this.isolated.traverse((o) => {
        if (o.geometry !== this.geometry) o.geometry?.dispose();
        o.material?.dispose();
      });
      this.isolated = null;
    }
    for (const s of this.surfaces ?? []) s.visible = id === null;
    if (this.layers.inward) this.layers.inward.visible = id === null && this.visible.inward;
    if (this.layers.intersecting) this.layers.intersecting.visible = id === null && this.visible.intersecting;
    if (id === null || !this.mesh?.shells) {
      this.frameAll();
      return;
    }
    const shell = this.mesh.shells[id];
    const sub = this.shellGeometry(new Set([id]));
    const group = new THREE.Group();
    group.add(this.surface(THREE.FrontSide, 1), this.surface(THREE.BackSide, 4));
    for (const m of group.children) m.geometry = sub;
    if (shell.orientation === 'inward') group.children[0].material.color.set(colors.inward);
    group.userData.shell = id;
    this.isolated = group;
    this.model.add(group);
    this.frameBox(shell.bbox);
  }

  /** Frames an axis-aligned box { min, max } from the current viewing direction. */
  frameBox({ min, max }, animate = true) {
    const a = new THREE.Vector3(...min), b = new THREE.Vector3(...max);
    const centre = a.clone().add(b).multiplyScalar(0.5);
    const radius = Math.max(a.distanceTo(b) / 2, (this.diag || 1) * 0.02);
    const dir = this.camera.position.clone().sub(this.controls.target);
    this.lookAt(centre, radius, dir.lengthSq() > 0 ? dir : new THREE.Vector3(0.9, -1.5, 0.9), animate);
  }

  /**
   * Frames one defect (an item of mesh.defect(kind, i)) and highlights it: a loop for holes
   * and seams, the edge for edge defects, the point for a vertex, the corners of a triangle.
   */
  focusDefect(kind, item) {
    if (kind === 'holes' || kind === 'seams') {
      this.focusLoop({ vertices: item.vertices }, kind === 'holes' ? holeColor(item.id) : colors.seams);
      return;
    }
    const p = this.mesh.positions;
    const at = (v) => [p[3 * v], p[3 * v + 1], p[3 * v + 2]];
    let pts;
    if (kind === 'nonManifoldEdges' || kind === 'inconsistentEdges') pts = item.vertices.map(at);
    else if (kind === 'nonManifoldVertices') pts = [at(item.vertex)];
    else if (kind === 'selfIntersections' || kind === 'duplicateTriangles') {
      // Both triangles (the pair's point frames them too).
      pts = item.triangles.slice(0, 2).flatMap((t) => [0, 1, 2].map((c) => at(this.mesh.triangles[3 * t + c])));
    } else pts = [0, 1, 2].map((c) => at(this.mesh.triangles[3 * item.triangle + c]));
    const min = [0, 1, 2].map((k) => Math.min(...pts.map((q) => q[k])));
    const max = [0, 1, 2].map((k) => Math.max(...pts.map((q) => q[k])));
    this.frameBox({ min, max });
    this.setHighlight(null);
    const group = new THREE.Group();
    const color = kind === 'selfIntersections' ? colors.intersecting : kind === 'inconsistentEdges' ? colors.inconsistent
      : kind === 'nonManifoldEdges' ? colors.nonManifold
      : kind === 'nonManifoldVertices' ? colors.nonManifoldVertex : colors.seams;
    if (pts.length >= 2) {
      const segs = [];
      for (let i = 0; i < pts.length; i++) segs.push(...pts[i], ...pts[(i + 1) % pts.length]);
      const xyz = new Float32Array(pts.length === 2 ? segs.slice(0, 6) : segs);
      const white = new Float32Array(xyz.length).fill(1);
      const c = new THREE.Color(color);
      const rgb = new Float32Array(xyz.length);
      for (let i = 0; i < rgb.length; i += 3) rgb.set([c.r, c.g, c.b], i);
      group.add(this.lines(xyz, white, { width: 11, depthTest: false, order: 20 }));
      group.add(this.lines(xyz, rgb, { width: 6, depthTest: false, order: 21 }));
    }
    group.add(this.rings(pts.flat(), color));
    group.userData.defect = kind;
    this.highlight = group;
    this.model.add(group);
    this.requestRender();
  }

  /**
   * Draws a repair preview over the model (repair-panel.js), replacing the previous one:
   * `parts` is a list of { color, triangles (9 floats per triangle), boxes ([{ min, max }]),
   * segments (6 floats per segment), points (3 floats per point) }. Nothing of the mesh changes.
   */
  setPreview(parts) {
    this.clearPreview();
    if (!parts || !parts.length) return;
    const group = new THREE.Group();
    for (const part of parts) {
      const c = new THREE.Color(part.color);
      if (part.triangles?.length) {
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.Float32BufferAttribute(part.triangles, 3));
        const m = new THREE.Mesh(g, new THREE.MeshBasicMaterial({
          color: c, side: THREE.DoubleSide, transparent: true, opacity: 0.6, depthWrite: false,
          polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2,
        }));
        m.renderOrder = 8;
        group.add(m);
      }
      const segs = [...(part.segments ?? [])];
      for (const b of part.boxes ?? []) segs.push(...boxSegments(b));
      if (segs.length) {
        const xyz = new Float32Array(segs);
        const rgb = new Float32Array(xyz.length);
        for (let i = 0; i < rgb.length; i += 3) rgb.set([c.r, c.g, c.b], i);
        group.add(this.lines(xyz, rgb, { width: part.width ?? 2.5, depthTest: false, order: 16, opacity: 0.9 }));
      }
      if (part.points?.length) group.add(this.rings(part.points, part.color));
    }
    group.userData.preview = true;
    this.preview = group;
    this.model.add(group);
    this.requestRender();
  }

  clearPreview() {
    for (const key of ['preview', 'previewFocus']) {
      const g = this[key];
      if (!g) continue;
      this.model.remove(g);
      g.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
      this[key] = null;
    }
    this.requestRender();
  }

  /** Frames one box { min, max } of the preview and outlines it (white over `color`). */
  focusPreviewBox(box, color) {
    if (this.previewFocus) {
      this.model.remove(this.previewFocus);
      this.previewFocus.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
      this.previewFocus = null;
    }
    this.frameBox(box);
    const xyz = new Float32Array(boxSegments(box));
    const white = new Float32Array(xyz.length).fill(1);
    const c = new THREE.Color(color);
    const rgb = new Float32Array(xyz.length);
    for (let i = 0; i < rgb.length; i += 3) rgb.set([c.r, c.g, c.b], i);
    const group = new THREE.Group();
    group.add(this.lines(xyz, white, { width: 8, depthTest: false, order: 20 }));
    group.add(this.lines(xyz, rgb, { width: 4, depthTest: false, order: 21 }));
    this.previewFocus = group;
    this.model.add(group);
    this.requestRender();
  }

  /** Frames the whole model from a three-quarter view. */
  frameAll(animate = true) {
    if (!this.geometry) return;
    this.setHighlight(null);
    const s = this.geometry.boundingSphere;
    // A three-quarter view, turned towards the side where most holes open (one vote per hole:
    // the unit normal of its loop), so that holes under or behind the model face the camera.
    // Votes, not areas: the outer rim of an open sheet is a hole whose normal points backwards.
    const dir = new THREE.Vector3(0.9, -1.5, 0.9).normalize();
    const towardsHoles = new THREE.Vector3();
    for (const h of this.mesh?.holes ?? []) {
      const n = loopFrame(this.mesh, h.vertices).normal;
      if (n.lengthSq() > 0) towardsHoles.add(n.normalize());
    }
    if (towardsHoles.lengthSq() > 0) dir.add(towardsHoles.normalize().multiplyScalar(1.1)).normalize();
    this.lookAt(s.center, s.radius || 1, dir, animate);
  }

  /** Frames a hole (or seam) loop, looking into it from outside, and highlights it. */
  focusLoop(loop, color) {
    const f = loopFrame(this.mesh, loop.vertices);
    let dir = f.normal.clone();
    if (dir.lengthSq() < 1e-20) dir = this.camera.position.clone().sub(this.controls.target);
    // Look slightly off the loop's axis, so that the loop and its surroundings read in 3D.
    const side = new THREE.Vector3().crossVectors(dir, this.camera.up);
    if (side.lengthSq() < 1e-12) side.set(1, 0, 0);
    dir.normalize().add(side.normalize().multiplyScalar(0.35)).add(this.camera.up.clone().multiplyScalar(0.2));
    const radius = Math.max(f.radius * 1.6, this.diag * 0.02);
    this.lookAt(f.centre, radius, dir);
    this.setHighlight(loop, color);
  }

  setHighlight(loop, color) {
    if (this.highlight) {
      this.model.remove(this.highlight);
      this.highlight.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
      this.highlight = null;
    }
    if (!loop || !this.mesh) return;
    const group = new THREE.Group();
    const halo = loopSegments(this.mesh, [loop], () => '#ffffff');
    const core = loopSegments(this.mesh, [loop], () => color);
    group.add(this.lines(halo.xyz, halo.rgb, { width: 11, depthTest: false, order: 20 }));
    group.add(this.lines(core.xyz, core.rgb, { width: 6, depthTest: false, order: 21 }));
    this.highlight = group;
    this.model.add(group);
    this.requestRender();
  }
}

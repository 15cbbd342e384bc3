// The sample menu. Each `path` is a fixture under tests/fixtures/ (kept there once, with its licence
// in tests/fixtures/SOURCES.md); vite.config.js serves it at `samples/<file>` in dev and copies it
// into the static build. Entries with `generate` are built by generate.js in the page instead.
export const samples = [
  {
    id: 'bunny', group: 'Holes', label: 'Stanford bunny — holes in the base', file: 'bunny.stl',
    path: 'google_draco/testdata/STL/bunny.stl', credit: 'google/draco, Apache-2.0',
  },
  {
    id: 'sphere-with-hole', group: 'Holes', label: 'Sphere with a hole (ASCII)', file: 'sphereWithHole.stl',
    path: 'assimp_assimp/test/models/STL/sphereWithHole.stl', credit: 'assimp/assimp, BSD-3-Clause',
  },
  {
    id: 'colored-box', group: 'Holes', label: 'Coloured box, lid missing (generated, per-face colours)',
    generate: 'coloredOpenBox',
  },
  {
    id: 'unit-sphere', group: 'Closed', label: 'Unit sphere — watertight', file: 'unit_sphere.STL',
    path: 'mikedh_trimesh/models/unit_sphere.STL', credit: 'mikedh/trimesh, MIT',
  },
  {
    id: 'torus', group: 'Closed', label: 'Torus — watertight, genus 1', file: 'torus.STL',
    path: 'mikedh_trimesh/models/torus.STL', credit: 'mikedh/trimesh, MIT',
  },
  {
    id: 'xyz-cube', group: 'Closed', label: '20 mm calibration cube — watertight, Magics colour', file: '20mm-xyz-cube.stl',
    path: 'mikedh_trimesh/models/20mm-xyz-cube.stl', credit: 'mikedh/trimesh, MIT',
  },
  {
    id: 'shared', group: 'Broken', label: 'Two boxes sharing an edge — non-manifold', file: 'shared.STL',
    path: 'mikedh_trimesh/models/shared.STL', credit: 'mikedh/trimesh, MIT',
  },
  {
    id: 'triamid', group: 'Broken', label: 'Triangular pyramid — flipped faces', file: 'triamid.stl',
    path: 'wolph_numpy-stl/tests/stl_tests/triamid.stl', credit: 'wolph/numpy-stl, BSD-3-Clause',
  },
  {
    id: 'spider', group: 'Broken', label: 'Spider — flipped faces, seams, degenerate triangles', file: 'Spider_binary.stl',
    path: 'assimp_assimp/test/models/STL/Spider_binary.stl', credit: 'assimp/assimp, BSD-3-Clause',
  },
  {
    id: 'wrench', group: 'Broken', label: 'Wrench — non-manifold edges', file: 'wrench.stl',
    path: 'amandaghassaei_stl-parser/test/stl/wrench.stl', credit: 'amandaghassaei/stl-parser, MIT',
  },
  {
    id: 'box-overlapping', group: 'Broken', label: 'Box of 10 overlapping bodies — self-intersecting (Unite)', file: 'box.STL',
    path: 'mikedh_trimesh/models/box.STL', credit: 'mikedh/trimesh, MIT',
  },
  {
    id: 'torus-1m', group: 'Large', label: '1M-triangle torus with 8 holes (generated, 50 MB)',
    generate: 'bigTorus',
  },
];

export const defaultSampleId = 'bunny';

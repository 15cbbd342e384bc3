// manifold-3d as a judge of the shell report: every shell that stltopo calls closed,
// manifold and outward must build a Manifold with no error, and every shell it calls
// open or non-manifold must be rejected, on every fixture. The one place where the two
// definitions differ is asserted as such (see README, "Shells and defects"): manifold-3d
// pairs the half-edges of an edge that has as many sides one way as the other (two cubes
// sharing an edge) into separate edges and splits the vertices where a shell pinches, so
// a shell whose every side is paired builds there; stltopo calls an edge with more than
// two sides non-manifold, and a vertex with more than one vnext cycle too.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { loadStl, extractShell } from 'stltopo';
import Module from 'manifold-3d';
import { fixtures, manifoldVerdict } from './helpers.mjs';

const wasm = await Module();
wasm.setup();

// manifold-3d's verdict on one shell: 'NoError' or the error status it threw/reported.
const verdict = (part) => manifoldVerdict(wasm, part);

test('manifold-3d builds every closed, manifold, outward shell and rejects every open or non-manifold one', async () => {
  let built = 0, rejected = 0, pairedOnly = 0;
  for (const f of fixtures()) {
    let mesh;
    try {
      mesh = await loadStl(readFileSync(f), { shells: true });
    } catch {
      continue;
    }
    for (const sh of mesh.shells) {
      const v = verdict(extractShell(mesh, sh.id));
      const where = `${f} shell ${sh.id}: ${JSON.stringify(sh)} -> ${v}`;
      if (sh.closed && sh.manifold && sh.orientation === 'outward') {
        assert.equal(v, 'NoError', where);
        ++built;
      } else if (!sh.closed || !sh.manifold) {
        // Every side paired (no boundary edge, no cut side, so no seam): manifold-3d
        // separates such edges and pinched vertices and builds it; anything else it rejects.
        const everySidePaired = sh.boundaryEdges === 0 && sh.inconsistentEdges === 0 && sh.seams === 0;
        if (everySidePaired) {
          assert.equal(v, 'NoError', where);
          ++pairedOnly;
        } else {
          assert.notEqual(v, 'NoError', where);
          ++rejected;
        }
      }
    }
  }
  assert.ok(built >= 100 && rejected >= 150 && pairedOnly >= 3, `built ${built}, rejected ${rejected}, paired-only ${pairedOnly}`);
});

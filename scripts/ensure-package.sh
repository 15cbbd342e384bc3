#!/usr/bin/env bash
# Makes dist/ current: the one way that every entry point (npm start, build:demo, the Node,
# browser and bench tests) gets the package. Installs the npm dev dependencies when one is
# missing, then always runs the incremental build (scripts/build-wasm.sh: CMake rebuilds only
# what changed, the copy step leaves unchanged files alone), then checks that dist/ holds what
# that build made from the current sources (a C++ edit cannot leave a stale wasm in dist/).
set -euo pipefail
cd "$(dirname "$0")/.."
for m in vite/bin/vite.js three/package.json playwright-core/package.json typescript/package.json \
         @types/three/package.json three-mesh-halfedge/package.json manifold-3d/package.json; do
  if [ ! -f "node_modules/$m" ]; then
    npm install --no-audit --no-fund
    break
  fi
done
bash scripts/build-wasm.sh
BUILD_DIR="${STLTOPO_WASM_BUILD_DIR:-build-wasm}"
out="$BUILD_DIR/bindings/stltopo-wasm.wasm"
# bindings.cpp always reaches the link; the build's output must be newer than it.
newer=$(find bindings/bindings.cpp -newer "$out" 2>/dev/null | head -1)
if [ -n "$newer" ] || ! cmp -s "$out" dist/stltopo-wasm.wasm; then
  echo "ensure-package: dist/ is stale after the build (${newer:-dist/stltopo-wasm.wasm differs from $out})" >&2
  exit 1
fi

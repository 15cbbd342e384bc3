#!/usr/bin/env bash
# `npm run bench [-- OPTIONS]`: the benchmark of issue 7 (bench/run.mjs; --help lists OPTIONS).
#   npm run bench                 100k, 1M and 4M triangles (about half an hour on 2 cores)
#   npm run bench -- --quick      the 100k cases only (under a minute)
# Installs what it needs: admesh and libbenchmark-dev (scripts/deps.sh bench), the npm
# devDependencies three and three-mesh-halfedge, the wasm package in dist/ (built when it
# is missing or older than its sources), and the native harness in build-bench/.
# Tables go to stdout; progress and build logs to stderr.
# Env: JOBS (default 2), STLTOPO_BENCH_BUILD_DIR (default build-bench),
#      STLTOPO_BENCH_NO_WASM_REBUILD=1 keeps a stale dist/ (it is still built when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${JOBS:-2}"
BUILD_DIR="${STLTOPO_BENCH_BUILD_DIR:-build-bench}"

groups=(bench)
{ command -v cmake >/dev/null && command -v c++ >/dev/null; } || groups+=(native)
command -v node >/dev/null || groups+=(wasm)
bash scripts/deps.sh "${groups[@]}" >&2

if [ ! -f node_modules/three/package.json ] || [ ! -f node_modules/three-mesh-halfedge/package.json ]; then
  npm install --no-audit --no-fund >&2
fi

# The wasm package: rebuilt when missing or older than its sources (as scripts/test-node.sh).
stale=0
for f in stltopo-wasm.js stltopo-wasm.wasm index.js node.js core.js; do
  [ -f "dist/$f" ] || stale=1
done
if [ "$stale" = 0 ] && [ "${STLTOPO_BENCH_NO_WASM_REBUILD:-0}" != 1 ] &&
   [ -n "$(find src bindings web/src CMakeLists.txt scripts/build-wasm.sh -newer dist/stltopo-wasm.wasm -type f 2>/dev/null | head -1)" ]; then
  stale=1
fi
if [ "$stale" = 1 ]; then
  bash scripts/build-wasm.sh >&2
fi

# The native harness: genmesh, stltopo_stages, procstat and the CLI, Release.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_BUILD_BENCH=ON -DSTLTOPO_BUILD_TESTS=OFF >&2
cmake --build "$BUILD_DIR" -j"$JOBS" --target genmesh stltopo_stages procstat stltopo_cli >&2

export STLTOPO_BENCH_BUILD_DIR="$BUILD_DIR"
exec node bench/run.mjs "$@"

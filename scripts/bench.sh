#!/usr/bin/env bash
# `npm run bench [-- OPTIONS]`: the benchmark of issue 7 (bench/run.mjs; --help lists OPTIONS).
#   npm run bench                 100k, 1M and 4M triangles (about half an hour on 2 cores)
#   npm run bench -- --quick      the 100k cases only (under a minute)
# Installs what it needs: admesh and libbenchmark-dev (scripts/deps.sh bench), the npm
# devDependencies three and three-mesh-halfedge, the wasm package in dist/ (scripts/ensure-package.sh),
# and the native harness in build-bench/.
# Tables go to stdout; progress and build logs to stderr.
# Env: JOBS (default 2), STLTOPO_BENCH_BUILD_DIR (default build-bench; an existing Release build
#      directory may be named, its other options are kept),
#      STLTOPO_BENCH_NO_WASM_REBUILD=1 keeps dist/ as it is (it is still built when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${JOBS:-2}"
BUILD_DIR="${STLTOPO_BENCH_BUILD_DIR:-build-bench}"

bash scripts/deps.sh bench native wasm >&2

# The wasm package (scripts/ensure-package.sh: npm dev dependencies, incremental build).
# STLTOPO_BENCH_NO_WASM_REBUILD=1 measures dist/ as it is (e.g. an older build copied there).
if [ "${STLTOPO_BENCH_NO_WASM_REBUILD:-0}" != 1 ] || [ ! -f dist/stltopo-wasm.wasm ]; then
  STLTOPO_DEPS_INSTALLED=1 bash scripts/ensure-package.sh >&2
fi

# The stage harness compiled to wasm (bench/geometry.mjs: the pass in process, wasm against native),
# in the wasm build's directory (configured by scripts/build-wasm.sh; skipped when it is not).
WASM_BUILD_DIR="${STLTOPO_WASM_BUILD_DIR:-build-wasm}"
if [ -f "$WASM_BUILD_DIR/CMakeCache.txt" ]; then
  NODE_PATH="${NODE_PATH:-/usr/share/nodejs}" cmake --build "$WASM_BUILD_DIR" -j"$JOBS" --target stltopo_stages_wasm >&2
fi

# The native harness: genmesh, stltopo_stages, procstat and the CLI, Release. A fresh directory
# gets no tests; an existing one keeps its choice, so that STLTOPO_BENCH_BUILD_DIR=build (what
# scripts/test-bench-smoke.sh uses) adds the harness to the native test build and compiles the
# library once.
tests=()
[ -f "$BUILD_DIR/CMakeCache.txt" ] || tests=(-DSTLTOPO_BUILD_TESTS=OFF)
if [ -f "$BUILD_DIR/CMakeCache.txt" ] && ! grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$BUILD_DIR/CMakeCache.txt"; then
  echo "bench: $BUILD_DIR is not a Release build" >&2
  exit 1
fi
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_BUILD_BENCH=ON "${tests[@]}" >&2
cmake --build "$BUILD_DIR" -j"$JOBS" --target genmesh stltopo_stages procstat stltopo_edits stltopo_cli stltopo_repair_bench >&2
# CGAL's self_intersections for bench/geometry.mjs, when CGAL is installed (test-only).
# (grep reads the whole list: with pipefail, grep -q stopping at the match made cmake die of
# SIGPIPE and the test fail, so that the 2026-12-05 run had no CGAL figures.)
if cmake --build "$BUILD_DIR" --target help | grep stltopo_cgal_pmp >/dev/null; then
  cmake --build "$BUILD_DIR" -j"$JOBS" --target stltopo_cgal_pmp >&2
fi

export STLTOPO_BENCH_BUILD_DIR="$BUILD_DIR"
node bench/run.mjs "$@"
# The exact-geometry figures (issue 21): 100k and 1M tori, or 100k once with --quick or --tiny.
quick=0
for a in "$@"; do { [ "$a" = --quick ] || [ "$a" = --tiny ]; } && quick=1; done
if [ "$quick" = 1 ]; then
  node bench/weld.mjs --sizes 100k --reps 1 --out "$(mktemp -d)/weld.json"
  node bench/geometry.mjs --sizes 100k --reps 1 --out "$(mktemp -d)/geometry.json"
else
  node bench/weld.mjs
  node bench/geometry.mjs
fi
# Threads (issue 24): wasm against native on 1 and 2 threads, the 1M and 4M tori (bench/threads.mjs;
# issue 24 sets its two-thread target at 4M).
if [ "$quick" != 1 ]; then
  node bench/threads.mjs --sizes 1M,4M
fi
# The repair (issue 23): the default repair of a torus with 8 holes and 1% flipped faces.
if [ "$quick" = 1 ]; then
  node bench/repair.mjs --sizes 100k --reps 1 --out "$(mktemp -d)/repair.json"
else
  node bench/repair.mjs
fi

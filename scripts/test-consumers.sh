#!/usr/bin/env bash
# The consumer matrix (tests/bundlers/run.mjs): the packed package installed into a small
# app per bundler (Vite 5/7/8 build and dev server, webpack 5, esbuild, Rollup, a plain
# <script type="module"> page) and run in Chromium, plus a TypeScript consumer of the README.
# Builds what it needs: chromium, node_modules and the package in dist/
# (scripts/ensure-package.sh), the native CLI (the reference for the stats). The apps' own
# dependencies are installed once into STLTOPO_CONSUMERS_DIR (default ~/.cache/stltopo-consumers)
# and reused. Env: STLTOPO_CONSUMERS=vite5,webpack5,ts,... runs a subset.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh native wasm browser
export STLTOPO_DEPS_INSTALLED=1
bash scripts/ensure-package.sh >/dev/null
if [ ! -x build/stltopo ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j2 >/dev/null
fi
node --test --test-concurrency=1 tests/bundlers/run.mjs

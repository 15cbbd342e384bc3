#!/usr/bin/env bash
# `npm run bench:big [-- OPTIONS]`: how large a file loads (bench/big.mjs: --sizes 40M,
# --modes native,node,node-view,node-worker,chromium,demo). Builds the native harness
# (genmesh, procstat, the CLI), the package and the demo first. Each 40M-triangle file is
# 2 GB in bench/data/; a run of every mode takes some 10 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${JOBS:-2}"
BUILD_DIR="${STLTOPO_BENCH_BUILD_DIR:-build-bench}"
bash scripts/deps.sh native wasm browser >&2
STLTOPO_DEPS_INSTALLED=1 bash scripts/ensure-package.sh >&2
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_BUILD_BENCH=ON -DSTLTOPO_BUILD_TESTS=OFF >&2
cmake --build "$BUILD_DIR" -j"$JOBS" --target genmesh procstat stltopo_cli >&2
STLTOPO_PACKAGE_READY=1 bash scripts/build-demo.sh >&2
export STLTOPO_BENCH_BUILD_DIR="$BUILD_DIR"
node bench/big.mjs "$@"

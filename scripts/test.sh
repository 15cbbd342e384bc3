#!/usr/bin/env bash
# `npm test`: every test suite, in order: native (GoogleTest + reference check + CMake
# consumers), sanitizers and fuzz smoke, ThreadSanitizer on the threaded stages, Node (wasm
# package), browser (demo page).
# Installs what a fresh Debian machine lacks.
set -euo pipefail
cd "$(dirname "$0")/.."
# Every system package of every suite, once; the suites' own deps.sh calls are then no-ops.
bash scripts/deps.sh native wasm browser bench fuzz dask
export STLTOPO_DEPS_INSTALLED=1
step() {
  local name=$1; shift
  local t0=$SECONDS
  echo "=== $name"
  "$@"
  echo "=== $name: ok ($((SECONDS - t0)) s)"
}
step native bash scripts/test-native.sh
for s in test-sanitize test-tsan test-node test-browser test-consumers test-bench-smoke; do
  if [ -f "scripts/$s.sh" ]; then step "$s" bash "scripts/$s.sh"; fi
done
echo "=== all tests passed"

#!/usr/bin/env bash
# The Node half of `npm test` (scripts/test.sh builds build/stltopo first).
#   1. brings dist/ up to date (scripts/ensure-package.sh: incremental build, every time)
#   2. installs the npm devDependencies when they are missing, and chromium (deps.sh browser)
#   3. type-checks tests/js/types/api-usage.ts against the package's .d.ts (tsc --noEmit)
#   4. runs the Node tests in tests/js (node:test), including the npm pack smoke test
#   5. runs the GoogleTest suite compiled to wasm under Node (STLTOPO_WASM_GTEST=0 skips)
# Env: STLTOPO_NATIVE_CLI (default build/stltopo), STLTOPO_WASM_BUILD_DIR (default build-wasm),
#      STLTOPO_WASM_GTEST=0 (skip step 5), STLTOPO_WASM_GTEST_FILTER (gtest filter for step 5).
set -euo pipefail
cd "$(dirname "$0")/.."
export NODE_PATH="${NODE_PATH:-/usr/share/nodejs}"
BUILD_DIR="${STLTOPO_WASM_BUILD_DIR:-build-wasm}"
export STLTOPO_NATIVE_CLI="${STLTOPO_NATIVE_CLI:-$PWD/build/stltopo}"
if [ ! -x "$STLTOPO_NATIVE_CLI" ]; then
  echo "test-node: $STLTOPO_NATIVE_CLI is missing (scripts/test.sh builds it first)" >&2
  exit 1
fi

# 1-2. dist/ and the npm devDependencies (the one rule: scripts/ensure-package.sh), and chromium
# for tests/js/browser.test.mjs (the package in a real browser; skipped without it).
bash scripts/deps.sh wasm browser
export STLTOPO_DEPS_INSTALLED=1
bash scripts/ensure-package.sh

# 3. Types.
echo "test-node: tsc --noEmit (tests/js/types)"
node_modules/.bin/tsc -p tests/js/types/tsconfig.json

# 4. Node tests, two files at a time (one per core: 146 s against 190 s one at a time, as
# most of a file's time is one process waiting on a child CLI, a browser or its own single
# thread). The tests that time an abort compare it with a full load timed in the same process,
# so a neighbour slows both. --expose-gc lets the FinalizationRegistry test run.
echo "test-node: node --test tests/js"
node --expose-gc --test --test-concurrency=2 tests/js/*.test.mjs

# 5. The GoogleTest suite, compiled with Emscripten and run under Node.
if [ "${STLTOPO_WASM_GTEST:-1}" != 0 ] && [ ! -f /usr/src/googletest/googletest/src/gtest-all.cc ]; then
  echo "test-node: skipping the wasm GoogleTest run (no /usr/src/googletest; apt-get install libgtest-dev)"
elif [ "${STLTOPO_WASM_GTEST:-1}" != 0 ]; then
  emcmake cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_WASM_TESTS=ON >/dev/null
  cmake --build "$BUILD_DIR" --target stltopo_tests_wasm -j"${JOBS:-2}"
  # Tests that start the native CLI as a subprocess skip themselves in wasm (GTEST_SKIP).
  filter="${STLTOPO_WASM_GTEST_FILTER:-*}"
  # Two processes, each on every other test of the list (one wasm instance is one core; the
  # Emscripten runtime does not pass GTEST_SHARD_* from the environment, so the halves are
  # named). The tests already run side by side natively (ctest -j2).
  bin="$BUILD_DIR/tests/stltopo_tests_wasm.js"
  mapfile -t names < <(node "$bin" --gtest_filter="$filter" --gtest_list_tests |
    awk '/^[^ ]/ { suite = $1 } /^  / { print suite $1 }')
  if [ ${#names[@]} -eq 0 ]; then
    echo "test-node: no wasm GoogleTest matches $filter" >&2
    exit 1
  fi
  halves=("" "")
  for i in "${!names[@]}"; do halves[$((i % 2))]+="${names[$i]}:"; done
  echo "test-node: GoogleTest suite under Node (wasm), filter $filter: ${#names[@]} tests in 2 processes"
  tmp=$(mktemp -d)
  pids=()
  for k in 0 1; do
    [ -n "${halves[$k]}" ] || continue
    node "$bin" --gtest_filter="${halves[$k]%:}" >"$tmp/half$k.log" 2>&1 &
    pids+=("$k:$!")
  done
  status=0
  for kp in "${pids[@]}"; do
    k=${kp%%:*}
    if ! wait "${kp#*:}"; then status=1; fi
    cat "$tmp/half$k.log"
  done
  rm -rf "$tmp"
  [ $status -eq 0 ] || { echo "test-node: the wasm GoogleTest suite failed (above)" >&2; exit 1; }
fi

#!/usr/bin/env bash
# Browser test of the demo page (tests/demo/*.test.mjs): real Chromium (Debian `chromium`,
# driven by npm playwright-core) against a fresh static build of the demo. Builds what it needs:
# chromium, node_modules, the package in dist/ (scripts/ensure-package.sh), the native CLI (the
# reference for the stats). Screenshots land in test-artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh native wasm browser
export STLTOPO_DEPS_INSTALLED=1
bash scripts/ensure-package.sh
if [ ! -x build/stltopo ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j2 >/dev/null
fi
STLTOPO_PACKAGE_READY=1 bash scripts/build-demo.sh >/dev/null
mkdir -p test-artifacts
node --test --test-concurrency=1 tests/demo/

#!/usr/bin/env bash
# `npm start`: serves the demo page (web/demo) with Vite at http://localhost:${PORT:-5173}/.
# It first brings dist/ up to date (scripts/ensure-package.sh: npm dev dependencies, incremental
# wasm build), which the page imports exactly as npm users would. Does not open a browser.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh wasm
export STLTOPO_DEPS_INSTALLED=1
bash scripts/ensure-package.sh
echo "stltopo demo: http://localhost:${PORT:-5173}/  (Ctrl+C stops it)"
exec node node_modules/vite/bin/vite.js --config web/demo/vite.config.js \
  --port "${PORT:-5173}" --strictPort --clearScreen false

#!/usr/bin/env bash
# `npm start`: serves the demo page (web/demo) with Vite at http://localhost:${PORT:-5173}/.
# On a fresh clone it first installs the npm dev dependencies and builds the wasm package into
# dist/, which the page imports exactly as npm users would. Does not open a browser.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-package.sh
echo "stltopo demo: http://localhost:${PORT:-5173}/  (Ctrl+C stops it)"
exec node node_modules/vite/bin/vite.js --config web/demo/vite.config.js \
  --port "${PORT:-5173}" --strictPort --clearScreen false

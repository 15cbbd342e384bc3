#!/usr/bin/env bash
# `npm run build:demo`: writes the demo page as a static site to web/demo/dist/ (relative URLs,
# samples included), to be served from any folder of any static host. Builds the package first
# when dist/ lacks it. Extra arguments go to `vite build` (e.g. --outDir /tmp/site).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-package.sh
node node_modules/vite/bin/vite.js build --config web/demo/vite.config.js --logLevel warn "$@"
echo "build-demo: static site in web/demo/dist/ (try: npx vite preview --config web/demo/vite.config.js)"

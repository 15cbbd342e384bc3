#!/usr/bin/env bash
# `npm run build:demo`: writes the demo page as a static site to web/demo/dist/ (relative URLs,
# samples included), to be served from any folder of any static host. Brings dist/ up to date
# first (scripts/ensure-package.sh) unless the caller just did (STLTOPO_PACKAGE_READY=1).
# Extra arguments go to `vite build` (e.g. --outDir /tmp/site).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${STLTOPO_PACKAGE_READY:-0}" != 1 ]; then
  bash scripts/deps.sh wasm
  STLTOPO_DEPS_INSTALLED=1 bash scripts/ensure-package.sh
fi
node node_modules/vite/bin/vite.js build --config web/demo/vite.config.js --logLevel warn "$@"
echo "build-demo: static site in web/demo/dist/ (try: npx vite preview --config web/demo/vite.config.js)"

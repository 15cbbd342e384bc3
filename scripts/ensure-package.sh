#!/usr/bin/env bash
# Installs the npm dev dependencies when node_modules lacks them, and builds the package
# (scripts/build-wasm.sh) when a file that package.json "exports" is missing from dist/.
# Used by start.sh, build-demo.sh and test-browser.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f node_modules/vite/bin/vite.js ] || [ ! -f node_modules/three/package.json ] \
   || [ ! -f node_modules/playwright-core/package.json ]; then
  npm install --no-audit --no-fund
fi
missing=$(node -e '
  const fs = require("fs");
  const pkg = JSON.parse(fs.readFileSync("package.json", "utf8"));
  const files = [];
  const walk = (e) => typeof e === "string" ? files.push(e) : e && Object.values(e).forEach(walk);
  walk(pkg.exports);
  const missing = files.filter((f) => !f.includes("*") && !fs.existsSync(f));
  if (!files.length && !fs.existsSync("dist")) missing.push("dist/");
  console.log(missing.join(" "));
')
if [ -n "$missing" ]; then
  echo "ensure-package: building the package (missing: $missing)" >&2
  bash scripts/build-wasm.sh
fi

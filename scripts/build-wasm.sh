#!/usr/bin/env bash
# Builds the wasm core with Emscripten and assembles the npm package in dist/:
#   dist/stltopo-wasm.{js,wasm}  the Embind module (bindings/)
#   dist/*.js, dist/*.d.ts       the hand-written ESM layer (web/src/)
# Usage: scripts/build-wasm.sh            (npm run build; also prepack)
# Env:   STLTOPO_WASM_BUILD_DIR (default build-wasm), JOBS (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${STLTOPO_WASM_BUILD_DIR:-build-wasm}"
JOBS="${JOBS:-2}"

if ! command -v emcc >/dev/null 2>&1 || ! command -v emcmake >/dev/null 2>&1; then
  bash scripts/deps.sh wasm
fi
# Debian's emscripten runs its JS tools with the system node and needs its modules.
export NODE_PATH="${NODE_PATH:-/usr/share/nodejs}"
# Debian's package ships emscripten's system libraries prebuilt in its cache, so
# nothing needs to be written there (non-root builds work).
emcmake cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" --target stltopo_wasm -j"$JOBS"

# Update dist/ in place: files whose bytes did not change are left alone, so an
# up-to-date rebuild (e.g. prepack during the tests) never disturbs readers.
mkdir -p dist
new=("$BUILD_DIR/bindings/stltopo-wasm.js" "$BUILD_DIR/bindings/stltopo-wasm.wasm" web/src/*.js web/src/*.d.ts)
keep=()
for f in "${new[@]}"; do
  b=$(basename "$f")
  keep+=("$b")
  if ! cmp -s "$f" "dist/$b"; then
    cp "$f" "dist/.$b.tmp"
    mv -f "dist/.$b.tmp" "dist/$b"
  fi
done
for f in dist/* dist/.[!.]*; do
  [ -e "$f" ] || continue
  b=$(basename "$f")
  case " ${keep[*]} " in *" $b "*) ;; *) rm -rf "$f" ;; esac
done



# Size report: what a browser downloads (gzip -9), .wasm + glue.
w=$(gzip -9c dist/stltopo-wasm.wasm | wc -c)
g=$(gzip -9c dist/stltopo-wasm.js | wc -c)
echo "build-wasm: dist/ ready; stltopo-wasm.wasm $(wc -c <dist/stltopo-wasm.wasm) B ($w gz) + glue $(wc -c <dist/stltopo-wasm.js) B ($g gz) = $((w + g)) B gzipped"

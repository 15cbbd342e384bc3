#!/usr/bin/env bash
# Builds the wasm core with Emscripten and assembles the npm package in dist/:
#   dist/stltopo-wasm.{js,wasm}  the core Embind module: loads, the report, validate() (bindings/)
#   dist/stltopo-full.{js,wasm}  everything (shells, fromIndexed, writing, EditableMesh), loaded
#                                on the first use of one of those
#   dist/stltopo-{wasm,full}-mt.{js,wasm,worker.js}  the same two built with pthreads, for
#                                loads with threads > 1 (README, *Threads in JS*)
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
cmake --build "$BUILD_DIR" --target stltopo_wasm stltopo_full_wasm stltopo_wasm_mt stltopo_full_wasm_mt -j"$JOBS"

# Update dist/ in place: files whose bytes did not change are left alone, so an
# up-to-date rebuild (e.g. prepack during the tests) never disturbs readers.
mkdir -p dist
# The glue files are minified first (scripts/minify-glue.mjs: about a quarter of their
# gzipped size); the .wasm files are as emcc wrote them.
for m in wasm full wasm-mt full-mt; do
  f="$BUILD_DIR/bindings/stltopo-$m.js"
  if [ ! -f "$f.min" ] || [ "$f" -nt "$f.min" ] || [ scripts/minify-glue.mjs -nt "$f.min" ]; then
    node scripts/minify-glue.mjs "$f" "$f.min.tmp"
    mv -f "$f.min.tmp" "$f.min"
  fi
done
new=("$BUILD_DIR"/bindings/stltopo-{wasm,full}{,-mt}.js.min "$BUILD_DIR"/bindings/stltopo-{wasm,full}{,-mt}.wasm
     "$BUILD_DIR"/bindings/stltopo-{wasm,full}-mt.worker.js web/src/*.js web/src/*.d.ts)
keep=()
for f in "${new[@]}"; do
  b=$(basename "$f" .min)
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

# Only the full module may hold SIMD instructions and saturating float-to-int conversions (the
# intersection pass, src/CMakeLists.txt): the core must instantiate on every engine with wasm,
# SIMD or not. binaryen's wasm-dis comes with Emscripten. (grep reads the whole listing: with
# pipefail, grep -q would stop at the first match, wasm-dis would die of SIGPIPE, and the
# pipeline would count as no match.)
for m in wasm wasm-mt; do
  if command -v wasm-dis >/dev/null 2>&1 &&
     wasm-dis dist/stltopo-$m.wasm | grep -E '\b(v128|[if](8x16|16x8|32x4|64x2))\.|\.trunc_sat_' >/dev/null; then
    echo "build-wasm: stltopo-$m.wasm holds SIMD or saturating conversions; only stltopo-full(-mt) may" >&2
    exit 1
  fi
done

# Size report: what a browser downloads (gzip -9), .wasm + glue of each module. The first is
# what every load fetches; the budget (70 kB) is checked by tests/js/modules.test.mjs.
gz() { gzip -9c "$1" | wc -c; }
for m in wasm full wasm-mt full-mt; do
  w=$(gz dist/stltopo-$m.wasm)
  g=$(gz dist/stltopo-$m.js)
  echo "build-wasm: stltopo-$m.wasm $(wc -c <dist/stltopo-$m.wasm) B ($w gz) + glue $(wc -c <dist/stltopo-$m.js) B ($g gz) = $((w + g)) B gzipped"
done

#!/usr/bin/env bash
# Part of `npm test`: proves that the benchmark still runs, on tiny meshes only
# (bench/run.mjs --tiny: 3k triangles, one repetition, every contender). No timing
# assertion: it fails only when a contender fails, disagrees with stltopo about the mesh
# (vertex, hole and boundary-edge counts), or the JSON results lack a figure.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The harness joins the native test build when there is one (scripts/test-native.sh made it):
# the library is then compiled once, not again in build-bench.
if [ -f build/CMakeCache.txt ] && grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' build/CMakeCache.txt; then
  export STLTOPO_BENCH_BUILD_DIR=${STLTOPO_BENCH_BUILD_DIR:-build}
fi
if ! bash scripts/bench.sh --tiny --out "$tmp/smoke.json" >"$tmp/table.md" 2>"$tmp/log"; then
  cat "$tmp/log" "$tmp/table.md" >&2
  echo "bench smoke: FAILED" >&2
  exit 1
fi
node -e '
  const r = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const want = ["native", "native-cli", "wasm-read", "wasm-full", "wasm-view", "wasm-full-kept", "three", "three-kept", "three-halfedge", "admesh"];
  const binaryOnly = ["three-halfedge", "wasm-full-kept", "three-kept"];
  const bad = [];
  for (const c of r.cases) for (const k of want) {
    if (binaryOnly.includes(k) && c.format !== "binary") continue;
    const x = c.contenders[k];
    if (!x || !(x.timeMs > 0)) bad.push(`${c.id} ${k}`);
    if (k === "wasm-full-kept" && !(c.ratios.wasmFullVsThreeKept > 0)) bad.push(`${c.id} wasmFullVsThreeKept`);
  }
  if (r.cases.length !== 5 || r.targets.length !== 12 || bad.length) {
    console.error("bench smoke: missing figures:", bad.join(", ") || `${r.cases.length} cases, ${r.targets.length} targets`);
    process.exit(1);
  }
' "$tmp/smoke.json"
echo "bench smoke: ok, 5 cases x 10 contenders ($((SECONDS - start)) s)"

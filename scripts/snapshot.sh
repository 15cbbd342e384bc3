#!/usr/bin/env bash
# Writes what a behaviour-preserving change must keep, for every fixture and generated
# case, into DIR: `info --json` (exact, --tolerance 0.001, --shells --defects), `info`
# text, and the hash of every reader and topology array (tests/dump_arrays.cpp). Compare
# two snapshots with `diff -r`.   usage: scripts/snapshot.sh BUILD_DIR OUT_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?build dir}; out=${2:?out dir}
mkdir -p "$out"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
python3 tests/reference/gen_cases.py "$tmp/generated" >/dev/null
files=()
while IFS= read -r f; do files+=("$f"); done < <(find tests/fixtures "$tmp/generated" -type f ! -name '*.md' | LC_ALL=C sort)
for f in "${files[@]}"; do
  name=${f#"$tmp/"}
  "$build/stltopo" info --json "$f" 2>&1 | sed "s|$tmp/||g" >> "$out/info.jsonl" || true
  "$build/stltopo" info --json --tolerance 0.001 "$f" 2>&1 | sed "s|$tmp/||g" >> "$out/info-tol.jsonl" || true
  "$build/stltopo" info "$f" 2>&1 | sed "s|$tmp/||g" >> "$out/info.txt" || true
  "$build/stltopo" info --json --shells --defects "$f" 2>&1 | sed "s|$tmp/||g" >> "$out/info-shells.jsonl" || true
  "$build/tests/dump_arrays" "$f" | sed "s|$tmp/||g" >> "$out/arrays.txt"
done
echo "snapshot: ${#files[@]} files -> $out"

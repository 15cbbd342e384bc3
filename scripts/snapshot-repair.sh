#!/usr/bin/env bash
# Writes what a behaviour-preserving change to the repair must keep into DIR: for every
# fixture, judge file (admesh pairs, regression inputs) and generated case, under three
# option sets, the plan (`repair --plan`), the change log and exit status (`repair`), and
# the hash of the written file. Compare two snapshots with `diff -r`.
#   usage: scripts/snapshot-repair.sh BUILD_DIR OUT_DIR [EXTRA_STL...]
# (EXTRA_STL: larger inputs, such as `bench/data/torus-100k-holes8-flip1.stl`.)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?build dir}; out=${2:?out dir}; shift 2
mkdir -p "$out"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
python3 tests/reference/gen_cases.py "$tmp/generated" >/dev/null
files=()
while IFS= read -r f; do files+=("$f"); done < <(find tests/fixtures tests/judge "$tmp/generated" -type f -iname '*.stl' | LC_ALL=C sort)
files+=("$@")
sets=(
  ""
  "--steps duplicates,zero-area,stitch,orient,split-nonmanifold,fill-holes,small-shells --fill refine,fair --stitch-tolerance 0.01 --min-shell-triangles 20 --remove-walls"
  "--no-intersections --steps orient,fill-holes,small-shells,split-nonmanifold"
)
for i in "${!sets[@]}"; do
  for f in "${files[@]}"; do
    name=${f#"$tmp/"}
    # shellcheck disable=SC2086
    { echo "== $name"; "$build/stltopo" repair "$f" "$tmp/out.stl" --plan ${sets[$i]} 2>&1 || true; } | sed "s|$tmp/||g" >> "$out/plan-$i.jsonl"
    rm -f "$tmp/out.stl"
    # shellcheck disable=SC2086
    { echo "== $name"; "$build/stltopo" repair "$f" "$tmp/out.stl" ${sets[$i]} 2>&1; echo "exit $?"
      if [ -f "$tmp/out.stl" ]; then sha256sum < "$tmp/out.stl"; fi; } | sed "s|$tmp/||g" >> "$out/log-$i.jsonl" || true
  done
done
echo "snapshot-repair: ${#files[@]} files x ${#sets[@]} option sets -> $out"

#!/usr/bin/env bash
# Compares `stltopo info --json`, also with --shells --defects [--max-defects 2], with
# the independent Python reference (tests/reference/stl_reference.py, written from the
# issues' text) on every file under tests/fixtures, on generated cases
# (tests/reference/gen_cases.py) and on any extra files given as arguments. Also checks
# the reference itself against the numbers in the fixtures' MANIFEST and against the
# generated cases' expectations, checks exit statuses, and checks that one multi-file
# run and stdin (`-`, streamed) print the same objects as one run per file.
#
# usage: scripts/check-reference.sh [--fixtures-only] [--cli PATH] [FILE...]
#   --fixtures-only   skip the generated cases
#   --cli PATH        the CLI to test (default: $STLTOPO_CLI or build/stltopo)
# Exit status: 0 when everything agrees, 1 on any mismatch, 2 on usage errors.
set -u
cd "$(dirname "$0")/.." || exit 2

cli=${STLTOPO_CLI:-build/stltopo}
generated=1
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --fixtures-only) generated=0 ;;
    --cli) shift; cli=${1:?--cli needs a path} ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) extra+=("$1") ;;
  esac
  shift
done

if [ ! -x "$cli" ]; then
  echo "check-reference: no CLI at $cli (build it first: cmake -S . -B build && cmake --build build)" >&2
  exit 2
fi
py=${PYTHON:-python3}
export PYTHONDONTWRITEBYTECODE=1
ref=tests/reference/stl_reference.py
cmp=tests/reference/compare.py
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

files=()
while IFS= read -r f; do files+=("$f"); done < <(find tests/fixtures -type f ! -name '*.md' | LC_ALL=C sort)
if [ "$generated" = 1 ]; then
  "$py" tests/reference/gen_cases.py "$tmp/generated" || exit 2
  while IFS= read -r f; do files+=("$f"); done < <(find "$tmp/generated" -type f | LC_ALL=C sort)
fi
files+=("${extra[@]+"${extra[@]}"}")
if [ "${#files[@]}" -eq 0 ]; then echo "check-reference: no files" >&2; exit 2; fi

fail=0
step() { printf '\n### %s\n' "$*"; }

if [ "$generated" = 1 ]; then
  step "reference self-test on generated cases"
  "$py" tests/reference/gen_cases.py --check || fail=1
fi

step "reference on ${#files[@]} files (with the shell and defect lists)"
"$py" "$ref" --shells --defects "${files[@]}" > "$tmp/ref.jsonl"
if [ "$(wc -l < "$tmp/ref.jsonl")" -ne "${#files[@]}" ]; then
  echo "the reference crashed"; exit 1
fi
step "reference vs MANIFEST"
"$py" "$cmp" manifest "$tmp/ref.jsonl" || fail=1

step "CLI ($cli), one run per file"
: > "$tmp/cli.jsonl"; : > "$tmp/rc.tsv"
for f in "${files[@]}"; do
  timeout 120 "$cli" info --json "$f" > "$tmp/one.json" 2> "$tmp/one.err"
  rc=$?
  if [ "$rc" -gt 1 ] || [ ! -s "$tmp/one.json" ]; then
    echo "CLI exit status $rc on $f: $(head -c 300 "$tmp/one.err")"
    fail=1
  fi
  cat "$tmp/one.json" >> "$tmp/cli.jsonl"
  [ -z "$(tail -c 1 "$tmp/one.json")" ] || echo >> "$tmp/cli.jsonl"
  printf '%s\t%s\n' "$rc" "$f" >> "$tmp/rc.tsv"
done
step "CLI vs reference"
"$py" "$cmp" cli "$tmp/cli.jsonl" "$tmp/ref.jsonl" "$tmp/rc.tsv" || fail=1

step "CLI --shells --defects vs reference (and the other keys vs plain --json)"
timeout 600 "$cli" info --json --shells --defects "${files[@]}" > "$tmp/shells.jsonl" 2>/dev/null
"$py" "$cmp" shells "$tmp/shells.jsonl" "$tmp/ref.jsonl" - "$tmp/cli.jsonl" || fail=1
step "CLI --shells --defects --max-defects 2 vs reference cut to 2"
timeout 600 "$cli" info --json --shells --defects --max-defects 2 "${files[@]}" > "$tmp/shells2.jsonl" 2>/dev/null
"$py" "$cmp" shells "$tmp/shells2.jsonl" "$tmp/ref.jsonl" 2 || fail=1

step "CLI: one multi-file run vs one run per file"
timeout 600 "$cli" info --json "${files[@]}" > "$tmp/multi.jsonl" 2>/dev/null
"$py" "$cmp" same "$tmp/multi.jsonl" "$tmp/cli.jsonl" && echo "identical" || fail=1

step "CLI: stdin (-) vs path"
: > "$tmp/stdin.jsonl"
for f in "${files[@]}"; do
  timeout 120 "$cli" info --json - < "$f" >> "$tmp/stdin.jsonl" 2>/dev/null
done
"$py" "$cmp" same "$tmp/stdin.jsonl" "$tmp/cli.jsonl" && echo "identical" || fail=1

if [ -n "${KEEP_OUTPUT:-}" ]; then
  mkdir -p "$KEEP_OUTPUT" && cp "$tmp"/*.jsonl "$tmp/rc.tsv" "$KEEP_OUTPUT"/
  echo "outputs kept in $KEEP_OUTPUT"
fi
echo
if [ "$fail" = 0 ]; then echo "check-reference: all agree"; else echo "check-reference: MISMATCHES (see above)"; fi
exit "$fail"

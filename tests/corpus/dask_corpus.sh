#!/usr/bin/env bash
# scripts/dask_corpus.py on a LocalCluster over tests/fixtures prints the bytes the serial
# run prints (issue 24, item 5). Usage: dask_corpus.sh STLTOPO SOURCE_DIR.
# Needs Debian's python3-distributed for /usr/bin/python3 (scripts/deps.sh dask).
set -uo pipefail
cli=$1
cd "$2" || exit 1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
py=/usr/bin/python3
"$py" -c 'import distributed' || fail "no python3-distributed for $py (bash scripts/deps.sh dask)"

check() { # check NAME SCRIPT-ARGS -- INFO-ARGS (script args: after the binary)
  local name=$1; shift
  local dask=() info=()
  local x
  while [ "$1" != -- ]; do dask+=("$1"); shift; done
  shift
  info=("$@")
  "$cli" info "${info[@]}" >"$tmp/$name.serial.out" 2>"$tmp/$name.serial.err"
  echo $? >"$tmp/$name.serial.rc"
  timeout 120 "$py" scripts/dask_corpus.py --local 2 "$cli" "${dask[@]}" "${info[@]}" >"$tmp/$name.dask.out" 2>"$tmp/$name.dask.err"
  echo $? >"$tmp/$name.dask.rc"
  for x in out err rc; do
    cmp "$tmp/$name.serial.$x" "$tmp/$name.dask.$x" || { head -c 2000 "$tmp/$name.dask.err" >&2; fail "$name: $x differs"; }
  done
  [ -s "$tmp/$name.serial.out" ] || fail "$name: nothing printed"
}

n=$(find tests/fixtures -iname '*.stl' | wc -l)
check json -- --json tests/fixtures
[ "$(wc -l <"$tmp/json.dask.out")" -eq "$n" ] || fail "not one line per fixture"
[ "$(cat "$tmp/json.dask.rc")" = 1 ] || fail "failing fixtures: exit status 1 expected"
# Text (errors on stderr), several files per task, a list, a missing file in the middle.
find tests/fixtures/google_draco tests/fixtures/regress -iname '*.stl' | LC_ALL=C sort >"$tmp/list"
check text --batch 4 -- --shells --defects --list "$tmp/list" no/such/file.stl tests/fixtures/mikedh_trimesh
grep -q '^no/such/file.stl: invalid-argument: cannot open' "$tmp/text.dask.err" || fail "the missing file's error"
echo "dask corpus (LocalCluster): same bytes as the serial run ($n fixtures)"

#!/usr/bin/env bash
# Runs the CGAL judge over every STL under tests/fixtures and writes the table of
# tests/judge/fixtures-expected.txt (to standard output). A file that does not read gives its
# error code in place of the counts. usage: run_fixtures.sh JUDGE [FIXTURES_DIR]
set -uo pipefail
judge=$(realpath "$1") root=${2:-$(cd "$(dirname "$0")/../fixtures" && pwd)}
field() { sed -n "s/.*\"$1\":\([0-9.]*\).*/\1/p" <<<"$2"; }
list() { sed -n "s/.*\"$1\":\[\(.*\)\],\"$2\".*/\1/p" <<<"$3"; }
echo "# stltopo_cgal_judge over tests/fixtures (tests/judge/run_fixtures.sh); seconds: the pair search only"
echo "# file triangles zeroArea duplicateGroups pairs crossing touching coplanar seconds"
cd "$root/.." && find fixtures -iname '*.stl' | LC_ALL=C sort | while read -r f; do
  if ! out=$("$judge" --count-only "$f" 2>/tmp/judge-err.$$); then
    echo "$f error $(sed -n 's/.*"error":"\([^"]*\)".*/\1/p' /tmp/judge-err.$$)"
    continue
  fi
  zero=$(list zeroArea duplicateGroups "$out"); groups=$(list duplicateGroups pairs "$out")
  nzero=0; [ -n "$zero" ] && nzero=$(tr ',' '\n' <<<"$zero" | wc -l)
  ngroups=0; [ -n "$groups" ] && ngroups=$(grep -o '\[' <<<"[$groups" | tail -n +2 | wc -l)
  echo "$f $(field triangles "$out") $nzero $ngroups $(field pairs "$out") $(field crossing "$out") $(field touching "$out") $(field coplanar "$out") $(field seconds "$out")"
done
rm -f /tmp/judge-err.$$

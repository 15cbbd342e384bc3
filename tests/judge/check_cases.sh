#!/usr/bin/env bash
# ctest cgal_judge_cases: runs the CGAL judge on every case of CASEDIR/expected.txt and compares
# its counts (triangles, zero-area, duplicate groups, pairs, crossing, touching, coplanar) with
# the expected ones; also checks that --brute (every pair, no boxes) gives the same pairs.
# usage: check_cases.sh JUDGE CASEDIR
set -euo pipefail
judge=$1 dir=$2 fail=0 n=0
field() { sed -n "s/.*\"$1\":\([0-9]*\).*/\1/p" <<<"$2"; }
list() { sed -n "s/.*\"$1\":\[\(.*\)\],\"$2\".*/\1/p" <<<"$3"; }
while read -r file want; do
  case "$file" in ''|'#'*) continue ;; esac
  n=$((n + 1))
  out=$("$judge" "$dir/$file") || { echo "FAIL $file: the judge exited with $?"; fail=1; continue; }
  head=$(head -n1 <<<"$out")
  zero=$(list zeroArea duplicateGroups "$head")
  groups=$(list duplicateGroups pairs "$head")
  nzero=0; [ -n "$zero" ] && nzero=$(tr ',' '\n' <<<"$zero" | wc -l)
  ngroups=0; [ -n "$groups" ] && ngroups=$(grep -o '\[' <<<"[$groups" | tail -n +2 | wc -l)
  got="$(field triangles "$head") $nzero $ngroups $(field pairs "$head") $(field crossing "$head") $(field touching "$head") $(field coplanar "$head")"
  if [ "$got" != "$want" ]; then
    echo "FAIL $file: expected $want, got $got"; fail=1
  else
    echo "ok   $file: $got"
  fi
  brute=$("$judge" --brute "$dir/$file" | tail -n +2)
  if [ "$brute" != "$(tail -n +2 <<<"$out")" ]; then echo "FAIL $file: --brute gives other pairs"; fail=1; fi
done < "$dir/expected.txt"
[ "$n" -gt 0 ] || { echo "FAIL: no cases in $dir/expected.txt"; exit 1; }
exit $fail

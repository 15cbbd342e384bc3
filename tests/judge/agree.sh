#!/usr/bin/env bash
# ctest cgal_judge_agrees: stltopo's zero-area triangles, duplicate groups and intersecting
# pairs (with kinds) equal the CGAL judge's on every fixture and hand-built case.
#   agree.sh STLTOPO_CLI JUDGE REPO_ROOT
set -euo pipefail
root=$3
mapfile -t files < <(find "$root/tests/fixtures" "$root/tests/judge/cases" -iname '*.stl' | LC_ALL=C sort)
exec python3 "$root/tests/judge/agree.py" "$1" "$2" "${files[@]}"

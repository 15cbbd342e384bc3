#!/usr/bin/env bash
# Native build + GoogleTest (and the CLI's corpus tests, the Dask recipe among them) + the
# independent reference check + CMake consumers.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh native dask
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSTLTOPO_BUILD_TESTS=ON >/dev/null
cmake --build build -j2
(cd build && ctest --output-on-failure --no-tests=error -j2)

# Independent reference (Python, standard library only) on every fixture.
if [ -f scripts/check-reference.sh ] && command -v python3 >/dev/null; then
  bash scripts/check-reference.sh
fi

# Downstream use: add_subdirectory and find_package after cmake --install.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install build --prefix "$tmp/prefix" >/dev/null
fixture=tests/fixtures/google_draco/testdata/STL/bunny.stl
cmake -S tests/cmake-consumer -B "$tmp/a" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/a" -j2 >/dev/null
[ "$("$tmp/a/consumer" "$fixture")" = "holes 5" ]
cmake -S tests/cmake-consumer -B "$tmp/b" -DUSE_SUBDIRECTORY=ON -DSTLTOPO_SOURCE_DIR="$PWD" >/dev/null
cmake --build "$tmp/b" -j2 >/dev/null
[ "$("$tmp/b/consumer" "$fixture")" = "holes 5" ]
echo "consumers (find_package, add_subdirectory): ok"

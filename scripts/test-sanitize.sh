#!/usr/bin/env bash
# Sanitizers and fuzz smoke (part of `npm test`):
#  1. the native tests (GoogleTest, CLI included) built with ASan+UBSan in build-asan;
#  2. each libFuzzer target (clang, -fsanitize=fuzzer,address,undefined) for
#     FUZZ_SMOKE_SECONDS (default 10) on its seed corpus tests/fuzz/seeds/<target>, two at a
#     time, built in build-asan (edge coverage) when clang built it, else in build-fuzz.
# Installs clang and compiler-rt when missing. About 2-3 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh native fuzz

asan=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# 1. Native tests under ASan+UBSan (clang when present, else gcc).
# With clang, the same build holds the fuzz targets of step 2: its library gets the edge counters
# libFuzzer reads (no comparison tracing), which cost the tests nothing measurable (ctest 173 s
# against 178), where a separate build-fuzz compiled the library a second time (about 100 s).
if command -v clang++ >/dev/null; then cxx=clang++; cc=clang; else cxx=g++; cc=gcc; fi
fuzz=()
if [ $cxx = clang++ ]; then
  fuzz=(-DSTLTOPO_BUILD_FUZZ=ON "-DSTLTOPO_FUZZ_LIBRARY_FLAGS=-fsanitize-coverage=inline-8bit-counters,pc-table")
fi
t0=$SECONDS
CC=$cc CXX=$cxx cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTLTOPO_SANITIZE=ON \
  -DSTLTOPO_BUILD_TESTS=ON -DSTLTOPO_BUILD_CLI=ON "${fuzz[@]}" >/dev/null
cmake --build build-asan -j2
# The few loops that run whole pipelines over every fixture many times (repair, stitch, threads)
# skip the fixtures over 3 MB here (tests/stl_gen.h, skipLargeFixture): the four largest, which
# took most of this run's time; the Release run checks them all.
(cd build-asan && STLTOPO_TEST_FIXTURE_BYTES_MAX=${STLTOPO_TEST_FIXTURE_BYTES_MAX:-3000000} ASAN_OPTIONS=$asan \
  ctest --output-on-failure -j2)
echo "sanitizer build ($cxx, ASan+UBSan): tests passed ($((SECONDS - t0)) s)"

# 2. Fuzz smoke: every target on its seeds.
t0=$SECONDS
if [ ${#fuzz[@]} -gt 0 ]; then export FUZZ_BUILD_DIR=build-asan; fi
FUZZ_SMOKE_SECONDS=${FUZZ_SMOKE_SECONDS:-10} bash scripts/fuzz.sh
echo "fuzz smoke: ok ($((SECONDS - t0)) s)"

#!/usr/bin/env bash
# ThreadSanitizer on the threaded stages (issue 24): the library and the Threads suite
# (tests/test_threads.cpp, target stltopo_thread_tests) built with -fsanitize=thread (clang) in
# build-tsan, and its tests run there, so that a data race
# in a stage that splits over threads fails the run, even where the race happens to give the
# one-thread output. Installs clang and compiler-rt when missing.
#   bash scripts/test-tsan.sh          `npm test`'s part: the tests that run every way the read
#                                      welds, the repair and the intersection pass on threads
#                                      (about 1.5 minutes on 2 cores, most of it the build)
#   bash scripts/test-tsan.sh --all    `npm run test:tsan`: every Threads test, the CLI's
#                                      included (about 5 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh native fuzz
filter='Threads.TheRead*:Threads.FuzzSeeds*:Threads.RepairIsTheSame*:Threads.IntersectionLimits*'
targets=(stltopo_thread_tests)
if [ "${1:-}" = --all ]; then
  filter='Threads.*'
  targets+=(stltopo_cli)
fi
t0=$SECONDS
CC=clang CXX=clang++ cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTLTOPO_TSAN=ON \
  -DSTLTOPO_BUILD_TESTS=ON -DSTLTOPO_BUILD_CLI=ON >/dev/null
cmake --build build-tsan -j2 --target "${targets[@]}"
# halt_on_error: the first report stops the run with a failure (without it a report only
# changes the exit code at the end).
(cd build-tsan && TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1} \
  ./tests/stltopo_thread_tests --gtest_filter="$filter")
echo "ThreadSanitizer ($filter): tests passed ($((SECONDS - t0)) s)"

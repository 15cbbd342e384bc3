#!/usr/bin/env bash
# `npm run fuzz -- [--minutes N] [--target NAME]...`
# Builds the libFuzzer targets of tests/fuzz (clang, -fsanitize=fuzzer,address,undefined)
# in build-fuzz and runs them one after the other, N minutes each (default 10), growing
# the corpus build-fuzz/corpus/<target> (not committed; seeded from tests/fuzz/seeds/<target>).
# The full libFuzzer output goes to build-fuzz/<target>.log. A crash stops that target and
# leaves build-fuzz/artifacts/<target>/crash-* (exit status 1): turn it into a regression file
# in tests/fixtures/regress/ (see tests/fuzz/README.md).
# FUZZ_SMOKE_SECONDS=S: run each target S seconds on its seeds in a scratch corpus instead
# (scripts/test-sanitize.sh uses this), FUZZ_JOBS (default 2) targets at a time: each is one
# process on one core, so two finish in the time of one.
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=10
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes=$2; shift 2 ;;
    --minutes=*) minutes=${1#*=}; shift ;;
    --target) targets+=("$2"); shift 2 ;;
    --target=*) targets+=("${1#*=}"); shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_whole fuzz_stream fuzz_tolerance fuzz_number fuzz_write fuzz_edit fuzz_repair)
case "$minutes" in ''|*[!0-9]*) echo "fuzz.sh: --minutes needs a whole number" >&2; exit 2 ;; esac

bash scripts/deps.sh native fuzz
# FUZZ_BUILD_DIR: a build configured with STLTOPO_BUILD_FUZZ=ON already (scripts/test-sanitize.sh
# names its build-asan), built as it is; else build-fuzz, configured here.
B=${FUZZ_BUILD_DIR:-build-fuzz}
if [ -n "${FUZZ_BUILD_DIR:-}" ]; then
  if ! grep -q '^STLTOPO_BUILD_FUZZ:BOOL=ON$' "$B/CMakeCache.txt" 2>/dev/null; then
    echo "fuzz.sh: FUZZ_BUILD_DIR=$B is not a build configured with -DSTLTOPO_BUILD_FUZZ=ON" >&2
    exit 2
  fi
else
  CC=clang CXX=clang++ cmake -S . -B $B -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTLTOPO_BUILD_FUZZ=ON \
    -DSTLTOPO_SANITIZE=ON -DSTLTOPO_BUILD_TESTS=OFF -DSTLTOPO_BUILD_CLI=OFF >/dev/null
fi
cmake --build $B -j2 --target "${targets[@]}" >/dev/null

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:allocator_may_return_null=1:quarantine_size_mb=64}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Inputs up to 64 KiB; no single allocation above 256 MB (an absurd count must not drive
# one), 2 GB of memory and 10 s per input at most.
common=(-dict=tests/fuzz/stl.dict -max_len=65536 -malloc_limit_mb=256 -rss_limit_mb=2048 -timeout=10
        -print_final_stats=1)
seedsOf() {
  if [ -d "tests/fuzz/seeds/$1" ]; then echo "tests/fuzz/seeds/$1"
  else echo tests/fuzz/seeds/fuzz_whole; fi  # fuzz_write starts from the STL files too
}

# Smoke: FUZZ_JOBS targets at a time, each on its seeds in a scratch corpus; results in order.
if [ -n "${FUZZ_SMOKE_SECONDS:-}" ]; then
  jobs=${FUZZ_JOBS:-2}
  case "$jobs" in ''|*[!0-9]*|0) echo "fuzz.sh: FUZZ_JOBS needs a whole number > 0" >&2; exit 2 ;; esac
  status=0
  for ((i = 0; i < ${#targets[@]}; i += jobs)); do
    batch=("${targets[@]:i:jobs}")
    pids=()
    for t in "${batch[@]}"; do
      mkdir -p "$B/artifacts/$t"
      work=$(mktemp -d)
      ( rc=0
        "$B/tests/fuzz/$t" "${common[@]}" -artifact_prefix="$B/artifacts/$t/" -max_total_time="$FUZZ_SMOKE_SECONDS" \
          "$work" "$(seedsOf "$t")" >"$B/$t.smoke.log" 2>&1 || rc=$?
        rm -rf "$work"
        exit $rc ) &
      pids+=($!)
    done
    for k in "${!batch[@]}"; do
      t=${batch[$k]}
      log=$B/$t.smoke.log
      if wait "${pids[$k]}"; then
        echo "$t: $(grep -E '^#[0-9]+.*DONE' "$log" | tail -n 1 | sed -E 's/ +/ /g') in ${FUZZ_SMOKE_SECONDS} s"
      else
        tail -n 60 "$log" >&2
        echo "!!! $t failed; full log $log, input in $B/artifacts/$t/" >&2
        status=1
      fi
    done
  done
  exit $status
fi

status=0
for t in "${targets[@]}"; do
  bin=$B/tests/fuzz/$t
  seeds=$(seedsOf "$t")
  art=$B/artifacts/$t
  mkdir -p "$art"
  corpus=$B/corpus/$t
  log=$B/$t.log
  mkdir -p "$corpus"
  echo "--- $t: $minutes min, corpus $corpus, log $log"
  rc=0
  "$bin" "${common[@]}" -artifact_prefix="$art/" -max_total_time=$((minutes * 60)) "$corpus" "$seeds" >"$log" 2>&1 &
  pid=$!
  trap 'kill -INT $pid 2>/dev/null || true' INT TERM
  while kill -0 $pid 2>/dev/null; do
    sleep 30
    line=$(grep -aE '^#[0-9]+' "$log" | tail -n 1 | cut -d' ' -f1-14 || true)
    [ -z "$line" ] || echo "  $line"
  done
  wait $pid || rc=$?
  trap - INT TERM
  if [ $rc -ne 0 ]; then
    grep -aE 'ERROR|runtime error|fuzz check failed|Test unit written' "$log" | head -n 5 >&2 || true
    echo "!!! $t crashed (status $rc); full log $log, input in $art/" >&2
    status=1
  fi
  grep -aE '^#[0-9]+.*DONE|stat::number_of_executed_units' "$log" || true
done
exit $status

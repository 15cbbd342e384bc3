#!/usr/bin/env bash
# The native CLI at the end of its memory (`ulimit -v`): a report or a repair that runs out
# is that file's out-of-memory error, never a crash. Usage: cli_memory.sh STLTOPO. On a
# 30,000-triangle soup (a shell and a hole a triangle: `info --json --shells` is 11.5 MB):
#  - with one job the JSON report goes out in pieces as it is written, so under a 30 MB
#    limit it is still whole and the same bytes (it was built as one string, and the CLI
#    ended with `terminate called after throwing an instance of 'std::bad_alloc'`);
#  - under limits from 10 to 100 MB, `info --jobs 2` (reports held whole until their turn)
#    and `repair --plan` (its items and JSON) end with a status, each failing file with an
#    out-of-memory error JSON, and no signal.
# Not for the sanitizer builds (their shadow memory needs the address space). One malloc
# arena: under an address-space limit, glibc's per-thread arenas try (and fail) to map a
# new 64 MB heap on each allocation, and `info --jobs 2` then took 30 s instead of 0.3.
set -uo pipefail
export MALLOC_ARENA_MAX=1
cli=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
soup=$tmp/soup.stl
python3 - "$soup" <<'PY'
import struct, sys
n = 30000
with open(sys.argv[1], 'wb') as f:
    f.write(b'\0' * 80 + struct.pack('<I', n))
    for t in range(n):
        x, y = float(t % 200), float(t // 200)
        f.write(struct.pack('<12fH', 0, 0, 0, x, y, 0, x + 0.5, y + 1, 0, x, y, 1, 0))
PY
"$cli" info --json --shells "$soup" "$soup" >"$tmp/ref.out" || fail "the unlimited run"
[ "$(stat -c %s "$tmp/ref.out")" -gt 20000000 ] || fail "the reports are smaller than expected"
(ulimit -v 30000; exec "$cli" info --json --shells "$soup" "$soup") >"$tmp/one.out" 2>"$tmp/one.err"
rc=$?
[ $rc = 0 ] || fail "one job under 30 MB: exit status $rc, $(head -c 300 "$tmp/one.err")"
cmp -s "$tmp/ref.out" "$tmp/one.out" || fail "one job under 30 MB printed other bytes"
oom=0
for lim in $(seq 10000 10000 100000); do
  (ulimit -v "$lim"; exec "$cli" info --json --shells --jobs 2 "$soup" "$soup") >"$tmp/two.out" 2>"$tmp/two.err"
  rc=$?
  [ $rc -le 1 ] || fail "info --jobs 2 under $lim kB: exit status $rc, $(head -c 300 "$tmp/two.err")"
  [ "$(wc -l <"$tmp/two.out")" = 2 ] || fail "info --jobs 2 under $lim kB: not two lines"
  for k in 1 2; do
    sed -n "${k}p" "$tmp/two.out" >"$tmp/line"
    sed -n "${k}p" "$tmp/ref.out" | cmp -s - "$tmp/line" ||
      grep -q '^{"file":"[^"]*","error":{"code":"out-of-memory",' "$tmp/line" ||
      fail "info --jobs 2 under $lim kB, line $k: $(head -c 300 "$tmp/line")"
  done
  grep -q out-of-memory "$tmp/two.out" && oom=$((oom + 1))
  (ulimit -v "$lim"; exec "$cli" repair "$soup" "$tmp/r.stl" --plan) >"$tmp/r.out" 2>"$tmp/r.err"
  rc=$?
  case $rc in
    0 | 3) ;;
    1) grep -q '"code":"out-of-memory"' "$tmp/r.err" || fail "repair under $lim kB: $(head -c 300 "$tmp/r.err")" ;;
    *) fail "repair under $lim kB: exit status $rc, $(head -c 300 "$tmp/r.err")" ;;
  esac
done
[ $oom -gt 0 ] || fail "no limit made info --jobs 2 run out of memory"
echo "cli memory: ok ($oom limits ran out)"

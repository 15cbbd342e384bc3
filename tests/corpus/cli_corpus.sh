#!/usr/bin/env bash
# Corpus mode of the native CLI (issue 24, item 5): `info` over DIRs and --list, --jobs N.
# Usage: cli_corpus.sh STLTOPO SOURCE_DIR. Checks, on tests/fixtures:
#  - --jobs 1, 2, 3 and 8 print the same bytes (JSON and text, stdout and stderr);
#  - the DIR, the same files as arguments, and the same files in a --list (CRLF, blank
#    lines) print the same bytes;
#  - a missing file and a broken file in the middle print their error lines in place,
#    every other file is still reported, and the exit status is 1;
#  - a link loop in a DIR ends; --jobs 0 / 257 / x are usage errors (exit 2);
#  - the memory gate: --max-memory changes no byte; the files start in order, each while the
#    estimates of the files being read fit in the budget or alone (the hidden --test-jobs-log);
#    an input of unknown size (a FIFO) is read alone: the next one is not even opened.
set -uo pipefail
cli=$1
cd "$2" || exit 1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { # run NAME ARGS...: stdout, stderr and status in $tmp/NAME.{out,err,rc}
  local name=$1; shift
  "$cli" info "$@" >"$tmp/$name.out" 2>"$tmp/$name.err" </dev/null
  echo $? >"$tmp/$name.rc"
}
same() { # same A B: the two runs printed the same bytes with the same status
  for x in out err rc; do cmp -s "$tmp/$1.$x" "$tmp/$2.$x" || fail "$1 and $2 differ ($x)"; done
}

files=$(find tests/fixtures -iname '*.stl' | LC_ALL=C sort)
n=$(echo "$files" | wc -l)
[ "$n" -gt 50 ] || fail "only $n fixtures"
run j1 --json tests/fixtures
[ "$(wc -l <"$tmp/j1.out")" -eq "$n" ] || fail "not one line per fixture"
[ "$(cat "$tmp/j1.rc")" = 1 ] || fail "the fixtures include failing files: exit status 1 expected"
for j in 2 3 8; do run "j$j" --json --jobs "$j" tests/fixtures; same j1 "j$j"; done
run t1 --shells tests/fixtures
run t3 --shells --jobs 3 tests/fixtures
same t1 t3
grep -q ': truncated: ' "$tmp/t1.err" || fail "no failing file in the text run"
run g1 --json --intersections --defects --tolerance 0.001 tests/judge/cases tests/fixtures
run g3 --json --intersections --defects --tolerance 0.001 --jobs 3 tests/judge/cases tests/fixtures
same g1 g3

# The DIR, the files as arguments, the files in a list (CRLF and blank lines), mixed.
# shellcheck disable=SC2086
run args --json $files
same j1 args
{ echo; echo "$files" | sed 's/$/\r/'; echo; } >"$tmp/list"
run list --json --jobs 3 --list "$tmp/list"
same j1 list
"$cli" info --json --list - <"$tmp/list" >"$tmp/stdin.out" 2>"$tmp/stdin.err"; echo $? >"$tmp/stdin.rc"
same j1 stdin
first=$(echo "$files" | head -1)
run mixed --json "$first" --list "$tmp/list" tests/fixtures
[ "$(wc -l <"$tmp/mixed.out")" -eq $((2 * n + 1)) ] || fail "mixed inputs: wrong number of lines"
head -1 "$tmp/j1.out" | cmp -s - <(head -1 "$tmp/mixed.out") || fail "mixed inputs: not in order"

# A missing and a broken file in the middle; a good file after them.
good=tests/fixtures/google_draco/testdata/STL/bunny.stl
printf 'solid x\nfacet normal 0 0 0\n' >"$tmp/broken.stl"
for j in 1 3; do
  run "bad$j" --json --jobs "$j" "$good" no/such/file.stl "$tmp/broken.stl" tests/fixtures "$good"
  [ "$(cat "$tmp/bad$j.rc")" = 1 ] || fail "a failed file: exit status 1 expected"
  [ "$(wc -l <"$tmp/bad$j.out")" -eq $((n + 4)) ] || fail "a failed file stopped the rest"
  sed -n 2p "$tmp/bad$j.out" | grep -q '^{"file":"no/such/file.stl","error":{"code":"invalid-argument"' ||
    fail "the missing file's error line"
  sed -n 3p "$tmp/bad$j.out" | grep -q '"error":{"code":"' || fail "the broken file's error line"
  tail -1 "$tmp/bad$j.out" | grep -q "^{\"file\":\"$good\",\"format\":\"binary\"" || fail "the good file after them"
done
same bad1 bad3

# A link loop and a broken link in a DIR: the walk ends, the broken link is reported.
mkdir -p "$tmp/d/sub"
cp "$good" "$tmp/d/sub/A.STL"
ln -s .. "$tmp/d/sub/loop"
ln -s "$tmp/d" "$tmp/d/sub/loop2"
ln -s nothing.stl "$tmp/d/gone.stl"
timeout 20 "$cli" info --json --jobs 2 "$tmp/d" >"$tmp/loop.out"
[ $? = 1 ] || fail "the link loop: exit status 1 expected (the broken link)"
[ "$(wc -l <"$tmp/loop.out")" -eq 2 ] || fail "the link loop: two files expected"

# The memory gate. The log's lines: "start I ESTIMATE READING INFLIGHT" (the files being read
# and the sum of their estimates when I started) and "end I".
gate() { # gate NAME BUDGET JOBS: the log keeps the gate's rules
  awk -v budget="$2" -v jobs="$3" -v name="$1" '
    $2 == "start" {
      if ($3 != next_i) { print name ": file " $3 " started out of order"; bad = 1 }
      next_i = $3 + 1
      if ($5 > 0 && $6 + $4 > budget) { print name ": file " $3 " started beside " $5 " over the budget"; bad = 1 }
      if ($5 >= jobs) { print name ": more than " jobs " files at once"; bad = 1 }
      starts++
    }
    END { if (starts == 0) { print name ": no log"; bad = 1 } exit bad }' next_i=0 "$tmp/$1.err" || fail "the memory gate ($1)"
}
run m1 --json --jobs 3 --max-memory 1 tests/fixtures
same j1 m1
"$cli" info --json --jobs 3 --max-memory 1 --test-jobs-log tests/fixtures >"$tmp/m1log.out" 2>"$tmp/m1log.err"
cmp -s "$tmp/j1.out" "$tmp/m1log.out" || fail "--test-jobs-log changed the output"
gate m1log 1 1
[ "$(grep -c ' start ' "$tmp/m1log.err")" -eq "$n" ] || fail "the log has not every file"
for budget in 3000000 30000000; do
  "$cli" info --json --jobs 4 --max-memory $budget --test-jobs-log tests/fixtures >"$tmp/m$budget.out" 2>"$tmp/m$budget.err"
  cmp -s "$tmp/j1.out" "$tmp/m$budget.out" || fail "--max-memory $budget changed the output"
  gate "m$budget" $budget 4
done
grep -q ' start [0-9]* [0-9]* [1-9]' "$tmp/m30000000.err" || fail "a budget of 30 MB never read two files at once"
# Two FIFOs on --jobs 2: the second is not opened while the first waits for its writer (a
# non-blocking open for writing fails with ENXIO while no reader has the FIFO open).
mkfifo "$tmp/fa.stl" "$tmp/fb.stl"
"$cli" info --json --jobs 2 "$tmp/fa.stl" "$tmp/fb.stl" >"$tmp/fifo.out" 2>"$tmp/fifo.err" &
pid=$!
sleep 1
python3 - "$tmp/fb.stl" <<'PY' || fail "the second FIFO was opened while the first was read"
import errno, os, sys
try:
    os.close(os.open(sys.argv[1], os.O_WRONLY | os.O_NONBLOCK))
    sys.exit(1)
except OSError as e:
    sys.exit(0 if e.errno == errno.ENXIO else 1)
PY
cat "$good" >"$tmp/fa.stl"
cat "$good" >"$tmp/fb.stl"
wait $pid || fail "the FIFOs' run failed"
[ "$(wc -l <"$tmp/fifo.out")" -eq 2 ] && ! grep -q error "$tmp/fifo.out" || fail "the FIFOs' reports"
for bad in 0 x -1 '' 1.5; do
  "$cli" info --jobs 2 --max-memory "$bad" tests/fixtures >/dev/null 2>&1
  [ $? = 2 ] || fail "--max-memory '$bad' is a usage error"
done

for bad in 0 257 x -1 ''; do
  "$cli" info --jobs "$bad" tests/fixtures >/dev/null 2>&1
  [ $? = 2 ] || fail "--jobs '$bad' is a usage error"
done
"$cli" info --list "$tmp/nonexistent" >/dev/null 2>&1
[ $? = 2 ] || fail "an unreadable list is a usage error"
echo "cli corpus mode: ok ($n fixtures)"

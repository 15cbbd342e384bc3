#!/usr/bin/env bash
# Installs what a fresh Debian machine lacks. Usage: scripts/deps.sh native|wasm|browser|bench|fuzz|dask ...
# Each group is checked first and installed only when something is missing.
# A top-level command (scripts/test.sh, start.sh, bench.sh, ...) installs the union of what it
# needs once and exports STLTOPO_DEPS_INSTALLED=1; the scripts it runs then skip this check.
set -euo pipefail
[ "${STLTOPO_DEPS_INSTALLED:-0}" = 1 ] && exit 0
need=()
want() { dpkg -s "$1" >/dev/null 2>&1 || need+=("$1"); }
for group in "$@"; do
  case "$group" in
    native) want cmake; want g++; want make; want libgtest-dev; want pkg-config; want libcgal-dev ;;
    wasm) want emscripten; want nodejs ;;
    browser) want chromium ;;
    bench) want admesh; want libbenchmark-dev ;;
    fuzz) want clang; want libclang-rt-14-dev ;;
    dask) want python3-distributed ;;  # scripts/dask_corpus.py and its test (/usr/bin/python3)
    *) echo "deps.sh: unknown group $group" >&2; exit 2 ;;
  esac
done
if [ ${#need[@]} -gt 0 ]; then
  echo "deps.sh: installing ${need[*]}" >&2
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq >&2 || true
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >&2
fi

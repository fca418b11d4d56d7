#!/usr/bin/env bash
# Configures and builds budget-slam (Release) into build/. Usage: tools/build.sh [extra cmake args]
# Prints one line; the build's own output is in build/build.log (its end is shown if it fails).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
if [ ! -f build/CMakeCache.txt ]; then
  log="$(mktemp)"
  if ! cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@" > "$log" 2>&1; then
    cat "$log"; rm -f "$log"; exit 1
  fi
  mv "$log" build/configure.log
fi
SECONDS=0
if ! cmake --build build --parallel "$(nproc)" > build/build.log 2>&1; then
  tail -n 40 build/build.log
  echo "build: failed (the whole log: build/build.log)" >&2
  exit 1
fi
if grep -q -e "Building" -e "Linking" build/build.log; then
  echo "build: done in ${SECONDS} s (log: build/build.log)"
else
  echo "build: up to date"
fi

#!/usr/bin/env bash
# Set-up, Release build, then the demo: budget-slam on a shipped rawlog with config.ini.
# Usage: tools/demo.sh [extra budget-slam run arguments]
# Each demo writes a new folder out/demo/<date>-<time>: nothing is written over, nothing nests
# (out/ is where the README's commands write; git ignores it).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
"$root/tools/build.sh"
cd "$root"
out="out/demo/$(date +%Y%m%d-%H%M%S)"
n=1
while [ -e "$out" ]; do n=$((n + 1)); out="out/demo/$(date +%Y%m%d-%H%M%S)-$n"; done
mkdir -p out/demo
"$root/build/bin/budget-slam" run -c config.ini -o "$out" "$@"
echo
echo "demo outputs in $root/$out:"
ls "$out"

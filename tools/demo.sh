#!/usr/bin/env bash
# Set-up, Release build, then the demo: budget-slam on a shipped rawlog with config.ini.
# Usage: tools/demo.sh [extra budget-slam run arguments]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
"$root/tools/build.sh"
cd "$root"
out="OUT_demo"
"$root/build/bin/budget-slam" run -c config.ini -o "$out" --force "$@"
echo
echo "demo outputs in $root/$out:"
ls "$out"

#!/usr/bin/env bash
# Set-up, build, and the whole test suite.
# Inside the suite itself (the README test runs this file as printed; BUDGET_SLAM_IN_SUITE=1), it
# lists the suite's tests instead of running them again, which would never end.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/setup.sh"
"$root/tools/build.sh"
cd "$root/build"
if [ "${BUDGET_SLAM_IN_SUITE:-}" = 1 ]; then
  echo "test: inside the suite: $(ctest -N | tail -n 1 | tr -d '\n'), not run again from here"
  exit 0
fi
ctest --output-on-failure --parallel "$(nproc)" --timeout 900

#!/usr/bin/env bash
# Builds the tests labelled `sanitize` with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DBUDGET_SLAM_SANITIZE=ON, in build-sanitize/) and runs them: the hostile-input rawlog
# reader tests, the session state reader's and the wake-up's tests, and the fuzz corpus replays.
# Any sanitizer report fails the run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-sanitize"
# The executables holding the tests labelled `sanitize` (kept to the fast ones: CI time).
targets=(test_rawlog_reader test_fuzz_corpus test_session test_fuzz_session_corpus test_wakeup)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBUDGET_SLAM_SANITIZE=ON \
  "${launcher[@]}" >/dev/null
ninja -C "$build" -j"$(nproc)" "${targets[@]}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest -L sanitize --output-on-failure --parallel "$(nproc)" --timeout 300

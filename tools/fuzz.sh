#!/usr/bin/env bash
# Builds the libFuzzer targets with clang-14 (AddressSanitizer + UBSan) in build-fuzz/ and runs
# each for a given time on a copy of its committed seed corpus.
#   tools/fuzz.sh [SECONDS=600] [TARGET...]      targets: fuzz_rawlog fuzz_ini fuzz_session
#                                                fuzz_session_crc (structure-aware: CRC kept)
#                                                fuzz_map_folder
#                                                fuzz_convert_{isam,g2o,utias,freiburg}
#                                                (default: all, one after the other)
# A finding stops the target and leaves crash-*/oom-*/timeout-* in build-fuzz/fuzz/findings/;
# the grown corpus stays in build-fuzz/fuzz/corpus/<target>/ (the committed seeds are untouched).
# Each allocation above 1 GiB, or a process above 1 GiB resident, counts as a finding.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_rawlog fuzz_ini fuzz_session fuzz_session_crc fuzz_map_folder
  fuzz_convert_isam fuzz_convert_g2o fuzz_convert_utias fuzz_convert_freiburg)

build="$root/build-fuzz"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DBUDGET_SLAM_FUZZ=ON \
  "${launcher[@]}" >/dev/null
ninja -C "$build" -j"$(nproc)" "${targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for t in "${targets[@]}"; do
  corpus="$build/fuzz/corpus/$t"
  findings="$build/fuzz/findings"
  mkdir -p "$corpus" "$findings"
  seeds="$root/fuzz/corpus/${t#fuzz_}"
  echo "== $t: ${seconds} s, seeds $seeds"
  if ! "$build/fuzz/$t" -max_total_time="$seconds" -rss_limit_mb=1024 -malloc_limit_mb=1024 \
    -timeout=10 -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/$t-" \
    "$corpus" "$seeds" 2>&1 | tee "$build/fuzz/$t.log" | grep -E '^(#[0-9]+ +(INITED|DONE)|==|SUMMARY|stat::)'; then
    :
  fi
  if grep -qE 'ERROR: libFuzzer|SUMMARY: (Address|Undefined)|deadly signal|==ERROR' "$build/fuzz/$t.log"; then
    echo "== $t: FINDING, see $build/fuzz/$t.log"
    status=1
  else
    echo "== $t: no finding; corpus $(ls "$corpus" | wc -l) inputs"
  fi
done
exit $status

#!/bin/sh
# Builds the libFuzzer targets (tests/fuzz) with clang into build-fuzz/ and runs each one for
# SECONDS_PER_TARGET seconds (default 60) on a fresh copy of its seed corpus, with its
# dictionary where there is one. The repository is never written: the growing corpora live
# in build-fuzz/corpus/NAME, findings in build-fuzz/findings/NAME/ (with NAME.log).
# Prints one line per target with the executions it ran; exits 1 when any target found a
# crash, a leak, a hang (an input running over 10 s) or a broken promise: fix it, then keep
# the input as a regression in tests/fuzz/regressions/NAME/ (tests/test_fuzz_regressions).
# Downloads nothing; needs clang and libclang-rt-14-dev (scripts/install-deps.sh).
#
#   ./scripts/fuzz.sh [SECONDS_PER_TARGET]
set -eu
seconds=${1:-60}
case $seconds in '' | *[!0-9]*) echo "usage: $0 [SECONDS_PER_TARGET]" >&2 && exit 2 ;; esac
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
targets="obj ply rays hits cli differential"

# -O1 compiles faster than -O2 (CI builds this on 2 cores); the targets still run
# hundreds to hundreds of thousands of inputs a second.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -DNDEBUG" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DGRIDSCOPE_FUZZ=ON >/dev/null
cmake --build "$build" -j"${JOBS:-2}" --target fuzz_targets

# The loader targets write each input to a scratch file: keep that in memory when we can.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

failed=0
for t in $targets; do
  corpus=$build/corpus/$t
  findings=$build/findings/$t
  log=$build/findings/$t.log
  rm -rf "$corpus" "$findings"
  mkdir -p "$corpus" "$findings"
  cp "$root/tests/fuzz/corpus/$t/"* "$corpus/"
  dict=
  [ -f "$root/tests/fuzz/$t.dict" ] && dict=-dict=$root/tests/fuzz/$t.dict
  status=0
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=4096 -print_final_stats=1 -artifact_prefix="$findings/" $dict "$corpus" \
    >"$log" 2>&1 || status=$?
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  verdict=ok
  if [ "$status" -ne 0 ]; then
    verdict="FAILED (exit $status): $(grep -m 1 -E '^(==[0-9]+==ERROR|SUMMARY|fuzz_)' "$log" || true)"
    failed=1
  fi
  printf 'fuzz_%-13s %10s executions %6s corpus inputs  %s\n' "$t" "${executions:-?}" \
    "$(find "$corpus" -type f | wc -l)" "$verdict"
done
exit $failed

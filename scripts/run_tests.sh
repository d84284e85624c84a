#!/usr/bin/env bash
# Runs every socc test on a fresh Debian 12 machine (as root): installs the dependencies,
# builds with warnings as errors and ASan/UBSan, runs the unit and integration tests (real
# map_server processes over UDP multicast on loopback), then bounded libFuzzer runs.
# Exits non-zero on any failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="$(nproc)"
start=$SECONDS
passed=0
failed=0

section() { printf '\n==== %s (%ds) ====\n' "$1" "$((SECONDS - start))"; }

# Runs ctest in a build dir and adds its counts to the totals.
run_ctest() {
  local dir="$1"
  shift
  local log="$dir/ctest.log"
  ctest --test-dir "$dir" --output-on-failure --timeout 300 -j"$jobs" "$@" 2>&1 | tee "$log"
  local line
  line="$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -1)"
  if [ -z "$line" ]; then
    echo "run_tests: ctest in $dir did not report results" >&2
    failed=$((failed + 1))
    return
  fi
  local f t
  f="$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1/' <<<"$line")"
  t="$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\2/' <<<"$line")"
  passed=$((passed + t - f))
  failed=$((failed + f))
}

section "set-up"
bash scripts/setup.sh || { echo "run_tests: set-up failed"; exit 1; }
if [ ! -d "$root/../shared/data" ]; then
  echo "run_tests: note: ../shared/data is absent: data-dependent tests will be skipped"
fi

# One build serves both CI requirements: warnings are errors AND every test runs under
# AddressSanitizer + UndefinedBehaviorSanitizer (two full builds would not fit the time budget).
# Benchmarks need an optimised plain build: scripts/build.sh, then build/bench/*.
# Compile time is most of the CI run, so: -g1 (line tables only: sanitizer reports keep
# file:line; about 30 % less compile time than -g), the CLI11 mains at -O1 (SOCC_APP_MAIN_FLAGS
# in CMakeLists.txt), lld when installed (scripts/packages.txt; links several times faster) and
# a unity build (8 sources per compiler run: the heavy headers are parsed once per batch;
# 387 s instead of 628 s for this build, measured). Plain builds (scripts/build.sh) stay one
# file per run, so both must compile: no two sources may define the same internal name.
section "build (-Werror, ASan + UBSan)"
ci_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOCC_WERROR=ON -DSOCC_SANITIZE=ON -DSOCC_BUILD_BENCH=OFF
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
  -DSOCC_APP_MAIN_FLAGS=-O1 -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8)
if command -v ld.lld >/dev/null; then ci_flags+=(-DSOCC_LINKER=lld); fi
bash scripts/build.sh "$root/build-ci" "${ci_flags[@]}" || { echo "run_tests: build failed"; exit 1; }

section "tests (ASan + UBSan)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  run_ctest "$root/build-ci"

if [ -x scripts/fuzz.sh ]; then
  section "fuzzing (bounded)"
  if bash scripts/fuzz.sh -t "${SOCC_FUZZ_SECONDS:-5}"; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
fi

section "summary"
echo "run_tests: total time $((SECONDS - start)) s"
echo "socc: ${passed} passed, ${failed} failed"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Runs every socc test on a fresh Debian 12 machine (as root): installs the dependencies,
# builds with warnings as errors and ASan/UBSan, runs the unit and integration tests (real
# map_server processes over UDP multicast on loopback) and replays of every fuzz harness.
# The last line is "socc: N passed, N failed, N skipped". Exits non-zero on any failure, and
# when a test skips although ../shared/data is present (skips are only for a missing data folder).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="$(nproc)"
start=$SECONDS
passed=0
failed=0
skipped=0
skipped_names=()

section() { printf '\n==== %s (%ds) ====\n' "$1" "$((SECONDS - start))"; }

# Adds the counts of a ctest log to the totals. ctest counts skipped tests (GTEST_SKIP output,
# SKIP_RETURN_CODE 77) as passed in "N tests failed out of M", and lists them after it under
# "The following tests did not run:" as "(Skipped)"; disabled tests are listed there but are not
# in M.
count_ctest() {
  local log="$1" line
  line="$(grep -E '[0-9]+ tests failed out of [0-9]+' "$log" | tail -1)"
  if [ -z "$line" ]; then
    echo "run_tests: ctest did not report results ($log)" >&2
    failed=$((failed + 1))
    return
  fi
  local f t
  f="$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1/' <<<"$line")"
  t="$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\2/' <<<"$line")"
  local names=() name
  while IFS= read -r name; do names+=("$name"); done < <(awk '
    / tests failed out of / { summary = 1 }
    summary && /^The following tests did not run:/ { list = 1; next }
    list && !/^[ \t]+[0-9]+ - / { list = 0 }
    list { sub(/^[ \t]+[0-9]+ - /, ""); print }' "$log")
  local s=0
  for name in "${names[@]}"; do
    case "$name" in *"(Skipped)") s=$((s + 1)) ;; esac
  done
  passed=$((passed + t - f - s))
  failed=$((failed + f))
  skipped=$((skipped + ${#names[@]}))
  skipped_names+=("${names[@]}")
}

# Runs ctest in a build dir and adds its counts to the totals.
run_ctest() {
  local dir="$1"
  shift
  local log="$dir/ctest.log"
  ctest --test-dir "$dir" --output-on-failure --timeout 300 -j"$jobs" "$@" 2>&1 | tee "$log"
  count_ctest "$log"
}

section "set-up"
bash scripts/setup.sh || { echo "run_tests: set-up failed"; exit 1; }
if [ ! -d "$root/../shared/data" ]; then
  echo "run_tests: note: ../shared/data is absent: data-dependent tests will be skipped"
fi

# One build serves both CI requirements: warnings are errors AND every test runs under
# AddressSanitizer + UndefinedBehaviorSanitizer (two full builds would not fit the time budget).
# Benchmarks are built too, for their smoke tests (ctest label bench-smoke: they must run; no
# target judged); timing them needs an optimised plain build: scripts/build.sh, then build/bench/*.
# Compile time is most of the CI run, so: -g1 (line tables only: sanitizer reports keep
# file:line; about 30 % less compile time than -g), the CLI11 mains at -O1 (SOCC_APP_MAIN_FLAGS
# in CMakeLists.txt), the tests, benchmarks and fuzz replays at -O1 (SOCC_TEST_FLAGS: half of
# the compile time, about 25 % less of it; the code they exercise is in the -O2 libraries),
# lld when installed (scripts/packages.txt; links several times faster) and a unity build (8
# sources per compiler run: the heavy headers are parsed once per batch; 387 s instead of 628 s
# for this build, measured; 16 per run compiled no faster). Plain builds (scripts/build.sh)
# stay one file per run, so both must compile: no two sources may define the same internal name.
section "build (-Werror, ASan + UBSan)"
ci_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOCC_WERROR=ON -DSOCC_SANITIZE=ON -DSOCC_BUILD_BENCH=ON
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
  -DSOCC_APP_MAIN_FLAGS=-O1 -DSOCC_TEST_FLAGS=-O1 -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8)
if command -v ld.lld >/dev/null; then ci_flags+=(-DSOCC_LINKER=lld); fi
# ccache (scripts/packages.txt): a repeated run on the same machine recompiles only what changed.
if command -v ccache >/dev/null; then
  ci_flags+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
bash scripts/build.sh "$root/build-ci" "${ci_flags[@]}" || { echo "run_tests: build failed"; exit 1; }

section "tests (ASan + UBSan)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  run_ctest "$root/build-ci"

# Every fuzz harness already ran above (ctest -L fuzz: its seed corpus and fixed mutants under
# ASan + UBSan). Coverage-guided libFuzzer runs need a second, clang build (about 7 min here):
# only when asked for, SOCC_FUZZ_SECONDS=N (per harness); otherwise scripts/fuzz.sh by hand.
if [ -n "${SOCC_FUZZ_SECONDS:-}" ]; then
  section "fuzzing (libFuzzer, ${SOCC_FUZZ_SECONDS} s per harness)"
  if bash scripts/fuzz.sh -t "$SOCC_FUZZ_SECONDS"; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
fi

section "summary"
echo "run_tests: total time $((SECONDS - start)) s"
data_skips=0
if [ -d "$root/../shared/data" ] && [ "$skipped" -gt 0 ]; then
  data_skips=1
  echo "run_tests: FAIL: ${skipped} test(s) did not run although ../shared/data is present:"
  printf '  %s\n' "${skipped_names[@]}"
fi
echo "socc: ${passed} passed, ${failed} failed, ${skipped} skipped"
[ "$failed" -eq 0 ] && [ "$data_skips" -eq 0 ]

#!/usr/bin/env bash
# Bounded fuzzing of socc's untrusted-input paths with libFuzzer (clang, ASan + UBSan):
#   scripts/fuzz.sh [-t SECONDS_PER_HARNESS] [-b BUILD_DIR] [-j JOBS]
# Configures a separate build (default build-fuzz) with CC=clang CXX=clang++ -DSOCC_FUZZ=ON,
# builds only the harnesses, writes a seed corpus (fuzz_seeds) and runs every harness for
# SECONDS (default 15) with -max_total_time, JOBS (default: nproc) harnesses at a time.
# Crash inputs are kept in BUILD_DIR/fuzz-artifacts.
# Exits non-zero when a harness finds a crash, leak, timeout or out-of-memory, or fails to build.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-fuzz"
seconds=15
jobs="$(nproc)"
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -t | --time) seconds="$2"; shift 2 ;;
    -b | --build) build="$(realpath -m "$2")"; shift 2 ;;
    -j | --jobs) jobs="$2"; shift 2 ;;
    *) echo "fuzz.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ "$seconds" =~ ^[0-9]+$ ]] && [ "$seconds" -gt 0 ] || { echo "fuzz.sh: bad -t $seconds" >&2; exit 2; }
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }

# The libraries under test get coverage instrumentation too (fuzzer-no-link); only the
# harnesses link libFuzzer's main. -O1 with line tables only (-g1), as libFuzzer's docs suggest:
# about half the compile time of -O2 -g, same instrumentation, crash stacks keep file:line.
# A new build directory uses Ninja and lld when installed (scripts/packages.txt); a unity build
# (as run_tests.sh) compiles the libraries 8 sources at a time.
mkdir -p "$build"
extra=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then extra+=(-G Ninja); fi
if command -v ld.lld >/dev/null; then extra+=(-DSOCC_LINKER=lld); fi
CC=clang CXX=clang++ cmake "${extra[@]}" -S "$root" -B "$build" -DSOCC_FUZZ=ON -DSOCC_SANITIZE=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOCC_BUILD_TESTS=OFF -DSOCC_BUILD_BENCH=OFF \
  -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" -DCMAKE_C_FLAGS="-fsanitize=fuzzer-no-link" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  >"$build/configure.log" 2>&1 || { cat "$build/configure.log"; echo "fuzz.sh: configure failed" >&2; exit 1; }
cmake --build "$build" -j"$jobs" --target socc_fuzzers || { echo "fuzz.sh: build failed" >&2; exit 1; }

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/fuzz/fuzz_seeds" "$work/seeds" || { echo "fuzz.sh: fuzz_seeds failed" >&2; exit 1; }
artifacts="$build/fuzz-artifacts"
rm -rf "$artifacts" && mkdir -p "$artifacts"  # only this run's findings

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:allocator_may_return_null=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# One harness per core at a time (libFuzzer is single-threaded, so each still gets a full core
# for its SECONDS); results are reported in harnesses.txt order.
run_harness() {
  local harness="$1"
  local corpus="$work/corpus/$harness"
  local scratch="$work/tmp/$harness"  # TMPDIR of the harness: temp files and MAP_COMMAND file_dir
  mkdir -p "$corpus" "$scratch"
  [ -d "$work/seeds/$harness" ] && cp "$work/seeds/$harness"/* "$corpus"/
  TMPDIR="$scratch" "$build/fuzz/$harness" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
    -artifact_prefix="$artifacts/$harness-" "$corpus" >"$work/$harness.log" 2>&1
  echo $? >"$work/$harness.rc"
}
mapfile -t harnesses < <(grep -v '^$' "$build/fuzz/harnesses.txt")
echo "fuzz: ${#harnesses[@]} harnesses, ${seconds}s each, ${jobs} at a time"
running=0
for harness in "${harnesses[@]}"; do
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
  run_harness "$harness" &
  running=$((running + 1))
done
wait

failed=()
passed=0
for harness in "${harnesses[@]}"; do
  log="$work/$harness.log"
  rc="$(cat "$work/$harness.rc" 2>/dev/null || echo 1)"
  printf '== %-28s %ss ... ' "$harness" "$seconds"
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  cov="$(grep -o 'cov: [0-9]*' "$log" | tail -1)"
  if [ "$rc" -eq 0 ]; then
    passed=$((passed + 1))
    echo "ok (${execs:-?} runs, ${cov:-cov: ?})"
  else
    failed+=("$harness")
    echo "FAILED (exit $rc)"
    grep -E "ERROR|SUMMARY|runtime error|Test unit written|==[0-9]+==" "$log" | head -20 | sed 's/^/   /'
    cp "$log" "$artifacts/$harness.log"
  fi
done

echo "fuzz: ${#failed[@]} of $((passed + ${#failed[@]})) harnesses found problems${failed:+: ${failed[*]}}"
[ ${#failed[@]} -eq 0 ]

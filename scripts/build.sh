#!/usr/bin/env bash
# Configures and builds socc. Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
# New build directories use Ninja when it is installed (faster than Makefiles, and its
# .ninja_log records per-target build times); an existing one keeps its generator.
# SOCC_BUILD_TARGETS="t1 t2": build only these (and what they need), e.g. the demo's programs
# without the tests.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
shift || true
generator=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
cmake "${generator[@]}" -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
targets=()
for t in ${SOCC_BUILD_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build" -j"$(nproc)" "${targets[@]}"

#!/usr/bin/env bash
# Configures and builds socc. Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
# New build directories use Ninja when it is installed (faster than Makefiles, and its
# .ninja_log records per-target build times); an existing one keeps its generator.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
shift || true
generator=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
cmake "${generator[@]}" -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build" -j"$(nproc)"

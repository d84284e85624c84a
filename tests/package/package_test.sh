#!/usr/bin/env bash
# The installed package works for another program: installs BUILD into a staging prefix, checks
# the layout and every binary's --version, builds examples/socc-monitor against that prefix
# (find_package(socc), CMAKE_PREFIX_PATH) and a one-file program with socc.pc, then runs the
# example against the staged map_server over udpm://239.x.y.z:port?ttl=0 (test_env.sh).
#   package_test.sh BUILD_DIR SOURCE_DIR VERSION CXX_COMPILER
set -euo pipefail
build="$1" src="$2" version="$3" cxx="$4"
source "$src/tests/integration/test_env.sh"
work="$(mktemp -d)"
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
prefix="$work/prefix"

cmake --install "$build" --prefix "$prefix" >"$work/install.log" || fail "cmake --install"
source "$src/tests/package/installed_tree.sh"
installed=()
for f in bin/map_server bin/socc-cli include/socc/rpc/map_client.hpp include/socc/map_stats_t.hpp \
  include/socc/version.hpp lib/cmake/socc/soccConfig.cmake lib/pkgconfig/socc.pc \
  share/socc/lcmtypes/map_stats_t.lcm share/socc/map_server/server.yaml etc/socc/server.yaml \
  share/socc/odom_client/default.yaml share/socc/odom_client/baseline.yaml \
  share/man/man1/map_server.1 share/man/man1/odom_client.1 \
  lib/systemd/system/socc-map-server.service share/socc/systemd/socc-map-server-lan.conf \
  libexec/socc/socc-ros1-bag-reader; do
  installed+=("$prefix/$f")
done
check_installed_tree "$prefix/lib/systemd/system/socc-map-server.service" "$prefix/bin" \
  "$prefix/bin" "$version" "${installed[@]}"

# The example, configured against the staging prefix only (not the build tree).
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake "${generator[@]}" -S "$src/examples/socc-monitor" -B "$work/example" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release \
  >"$work/example.log" 2>&1 || { cat "$work/example.log"; fail "example: configure"; }
cmake --build "$work/example" >>"$work/example.log" 2>&1 || { cat "$work/example.log"; fail "example: build"; }
monitor="$work/example/socc-monitor"
"$monitor" --help | grep -q "usage: socc-monitor" || fail "socc-monitor --help"
"$monitor" --version | grep -qx "socc-monitor (socc) $version" || fail "socc-monitor --version"

# pkg-config: the flags of socc.pc compile and link a client.
printf '#include "socc/rpc/map_client.hpp"\n#include <iostream>\nint main() { std::cout << socc::rpc::statusName(0) << "\\n"; }\n' >"$work/pc.cpp"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
[ "$(pkg-config --modversion socc)" = "$version" ] || fail "pkg-config --modversion socc"
# shellcheck disable=SC2046
"$cxx" -std=c++17 "$work/pc.cpp" -o "$work/pc" $(pkg-config --cflags --libs socc) || fail "socc.pc: compile"
"$work/pc" >/dev/null || fail "socc.pc: program"

# Against the staged map_server: GET_STATS carries the server's version.
require_multicast_on_loopback
url="$(random_lcm_url 21000)"
"$prefix/bin/map_server" --lcm-url "$url" --quiet --status-period 0 &
server_pid=$!
"$monitor" --lcm-url "$url" --timeout-ms 3000 >"$work/monitor.txt" || { cat "$work/monitor.txt"; fail "socc-monitor"; }
grep -q "^server $version " "$work/monitor.txt" || { cat "$work/monitor.txt"; fail "server version"; }
grep -q "no robot in the map" "$work/monitor.txt" || fail "an empty map has no robot"
echo "package: install, example (find_package), socc.pc and a live query OK"

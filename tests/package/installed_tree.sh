#!/usr/bin/env bash
# Sourced by package_test.sh and deb_test.sh (which define fail): checks one installed tree.
# check_installed_tree UNIT EXEC_BINDIR RUN_BINDIR VERSION FILE...
#   every FILE exists; the systemd unit UNIT starts EXEC_BINDIR/map_server; every binary in
#   RUN_BINDIR prints "NAME (socc) VERSION" for --version and has --help.
check_installed_tree() {
  local unit=$1 exec_bindir=$2 run_bindir=$3 version=$4 f exe
  shift 4
  for f in "$@"; do
    [ -e "$f" ] || fail "not installed: $f"
  done
  grep -q "^ExecStart=$exec_bindir/map_server " "$unit" ||
    fail "the systemd unit does not run $exec_bindir/map_server"
  for exe in map_server odom_client socc-cli socc-eval socc-sim socc-to-lcmlog socc-loadtest; do
    "$run_bindir/$exe" --version | grep -qx "$exe (socc) $version" || fail "$exe --version"
    "$run_bindir/$exe" --help >/dev/null || fail "$exe --help"
  done
}

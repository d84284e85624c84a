#!/usr/bin/env bash
# The .deb of BUILD: cpack -G DEB, its Debian dependencies (dpkg-shlibdeps) and contents, and the
# binaries run from the unpacked tree (dpkg-deb -x: no root, no chroot). Skips (77) without
# dpkg-deb (not a Debian system).
#   deb_test.sh BUILD_DIR VERSION
set -euo pipefail
build="$1" version="$2"
command -v dpkg-deb >/dev/null || { echo "SKIP: dpkg-deb not found"; exit 77; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

cpack -G DEB -B "$work/out" --config "$build/CPackConfig.cmake" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; fail "cpack -G DEB"; }
deb="$(ls "$work"/out/socc_"${version}"_*.deb)" || fail "no socc_${version}_*.deb"
dpkg-deb -I "$deb" >"$work/info.txt"
cat "$work/info.txt"
grep -q "^ Version: $version$" "$work/info.txt" || fail "package version"
for dep in liblcm1 libyaml-cpp libssl3 libstdc++6 libpcl-io; do
  grep -q "^ Depends:.*$dep" "$work/info.txt" || fail "Depends lacks $dep"
done
dpkg-deb -x "$deb" "$work/root"
root="$work/root"
source "$(dirname "$0")/installed_tree.sh"
check_installed_tree "$root/usr/lib/systemd/system/socc-map-server.service" /usr/bin \
  "$root/usr/bin" "$version" "$root/etc/socc/server.yaml" \
  "$root/usr/include/socc/rpc/map_client.hpp" "$root/usr/lib/cmake/socc/soccConfig.cmake" \
  "$root/usr/libexec/socc/socc-ros1-bag-reader"
echo "deb: $(basename "$deb") OK"

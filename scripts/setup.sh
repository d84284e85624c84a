#!/usr/bin/env bash
# Idempotent machine set-up for socc on Debian 12 (run as root):
#  1. installs the Debian packages listed in scripts/packages.txt (only the missing ones);
#  2. routes multicast to loopback and raises socket buffers, so LCM UDP multicast
#     (udpm://239.x.y.z:port?ttl=0) stays on this machine and large messages fit.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

mapfile -t wanted < <(grep -v '^\s*#' "$here/packages.txt" | sed 's/\s.*//' | grep -v '^$')
missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  # force-unsafe-io: dpkg skips its per-file fsync (what Debian's container images do); about
  # 800 packages are unpacked on a fresh machine, most of them pulled in by libpcl-dev.
  apt-get install -y -q --no-install-recommends -o Dpkg::Options::=--force-unsafe-io "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

# Multicast on loopback: LCM's udpm provider joins 239.x groups; with this route the
# traffic never reaches a real network interface.
if [ "$(id -u)" = 0 ]; then
  ip link set lo multicast on
  ip route replace 224.0.0.0/4 dev lo
  # Large LCM messages (scans, chunks) need big receive buffers.
  sysctl -q -w net.core.rmem_max=67108864 net.core.rmem_default=67108864 \
    net.core.wmem_max=67108864 || echo "setup: warning: could not raise socket buffers"
else
  echo "setup: not root: skipping the multicast route; run as root or see README.md" >&2
fi
echo "setup: done"

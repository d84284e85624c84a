#!/usr/bin/env bash
# Sourced by fleet_test.sh: a private LAN of network namespaces for multi-host tests.
#
# netns_lan_create PREFIX HOST...: namespace PREFIX-lan holds bridge br0; every HOST gets
#   namespace PREFIX-HOST with lo and eth0 (a veth whose peer is a port of br0), address
#   10.77.0.<n>/24 (n = 1, 2, ... in the order given) and the multicast route 224.0.0.0/4 via
#   eth0. Every link is created inside these namespaces and joined only to them: nothing
#   touches a real interface, and the addresses exist only in the namespaces.
# netns_lan_loss PREFIX HOST PERCENT: drops PERCENT % of the IPv4 packets (each IP fragment on
#   its own, as a lossy radio would) leaving and entering HOST's eth0 (nftables, netdev family
#   ingress + egress hooks).
# netns_lan_delete PREFIX: kills what still runs in the namespaces and deletes them.
# in_host PREFIX HOST CMD...: runs CMD in HOST's namespace.

netns_lan_hosts=()

netns_lan_create() {
  local prefix=$1 n=0 host
  shift
  netns_lan_hosts=(lan "$@")
  ip netns add "$prefix-lan" || return 1
  ip -n "$prefix-lan" link set lo up
  # No IGMP snooping: the bridge floods the group to every port, like a plain switch.
  ip -n "$prefix-lan" link add br0 type bridge mcast_snooping 0 || return 1
  ip -n "$prefix-lan" link set br0 up
  for host in "$@"; do
    n=$((n + 1))
    ip netns add "$prefix-$host" || return 1
    ip -n "$prefix-$host" link set lo up
    # Created inside the host's namespace, its peer moved straight into the LAN namespace.
    ip -n "$prefix-$host" link add eth0 type veth peer name "port$n" netns "$prefix-lan" || return 1
    ip -n "$prefix-lan" link set "port$n" master br0 up
    ip -n "$prefix-$host" addr add "10.77.0.$n/24" dev eth0
    ip -n "$prefix-$host" link set eth0 multicast on up
    ip -n "$prefix-$host" route add 224.0.0.0/4 dev eth0
  done
}

netns_lan_loss() {
  local prefix=$1 host=$2 permille
  permille=$(awk -v p="$3" 'BEGIN { printf "%d", p * 10 + 0.5 }')
  in_host "$prefix" "$host" nft -f - <<EOF
table netdev socc_loss {
  chain ingress { type filter hook ingress device eth0 priority 0; meta protocol ip numgen random mod 1000 < $permille counter drop; }
  chain egress { type filter hook egress device eth0 priority 0; meta protocol ip numgen random mod 1000 < $permille counter drop; }
}
EOF
}

netns_lan_delete() {
  local prefix=$1 host pid
  for host in "${netns_lan_hosts[@]}"; do
    ip netns list | grep -q "^$prefix-$host\b" || continue
    # Only processes of these namespaces, i.e. the ones the test started there.
    for pid in $(ip netns pids "$prefix-$host" 2>/dev/null); do kill -9 "$pid" 2>/dev/null || true; done
    ip netns del "$prefix-$host" 2>/dev/null || true
  done
}

in_host() {
  local prefix=$1 host=$2
  shift 2
  ip netns exec "$prefix-$host" "$@"
}

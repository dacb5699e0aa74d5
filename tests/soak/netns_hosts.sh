# Hosts on one machine, for the tests that need several (sourced by netns.sh and partition.sh):
# a bridge in a namespace of its own, and hosts joined to it by veth pairs.

# netns_hub HUB: the hub namespace with its bridge br0.
netns_hub() {
  ip netns add "$1"
  ip -n "$1" link add br0 type bridge
  ip -n "$1" link set br0 up
  ip -n "$1" link set lo up
}

# netns_host HUB NS N ADDRESS: host namespace NS on the hub's bridge as port pN, with ADDRESS/24
# on its eth0 and multicast (Cyclone's discovery) routed out of eth0. The pair is created inside
# the host's namespace and one end moved to the hub, so no interface ever appears in the
# machine's own namespace.
netns_host() {
  local hub="$1" ns="$2" n="$3" address="$4"
  ip netns add "$ns"
  ip -n "$ns" link set lo up
  ip -n "$ns" link add eth0 type veth peer name "p$n"
  ip -n "$ns" link set "p$n" netns "$hub"
  ip -n "$hub" link set "p$n" master br0
  ip -n "$hub" link set "p$n" up
  ip -n "$ns" addr add "$address/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" route add 224.0.0.0/4 dev eth0
}

#!/bin/bash
# Fleet across several hosts on one machine: one network namespace for fleet-server (and the
# soak's fleetctl), one per agent, joined by veth pairs on a bridge that lives in a namespace of
# its own. The links are degraded — random packet loss with iptables' statistic match (this
# kernel has no netem), a bandwidth cap with tbf — and the agents publish their poses late
# (faults.pose_delay_ms). Then a soak with faults runs across them and must pass.
#
# Everything stays inside the namespaces this script creates (10.77.0.0/24, names fleet-*);
# nothing touches the host's own interfaces or routes. The namespaces go when the script ends.
#
# usage (root): tests/soak/netns.sh [--duration S] [--loss P] [--agents N] [--site S] [--time-scale X]
#                                   [--security DIR] [--standby] [--faults LIST] [--json FILE] [--verbose]
# Up to 4 agents run on table_a at time scale 10; more run on mid_warehouse at time scale 1, where
# every agent has a home and the machine keeps up with them.
# --verbose: debug logs of every process in the run directory (the soak's --verbose).
# --security DIR: every process joins with DDS Security, its credentials from DIR (fleetctl
# security init; docs/security.md), across the namespaces' links.
# --standby: a standby server in a namespace of its own (a second server host); with
# --faults kill-host the active server is killed as its host dying would be, and comes back 5 s
# later as the other's standby.
# --faults LIST: the soak's faults (default kill-agent,stall-agent,kill-server,obstacles).
set -euo pipefail

duration=120
loss=0.02
agents=4
site=""
time_scale=""
json_out=""
verbose=()
security=()
standby=0
faults="kill-agent,stall-agent,kill-server,obstacles"
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --loss) loss="$2"; shift 2 ;;
    --agents) agents="$2"; shift 2 ;;
    --site) site="$2"; shift 2 ;;
    --time-scale) time_scale="$2"; shift 2 ;;
    --json) json_out="$2"; shift 2 ;;
    --verbose) verbose=(--verbose); shift ;;
    --security) security=(--security "$2"); shift 2 ;;
    --standby) standby=1; shift ;;
    --faults) faults="$2"; shift 2 ;;
    *) echo "netns.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

if [ "$agents" -le 4 ]; then
  site="${site:-table_a}"
  time_scale="${time_scale:-10}"
else
  site="${site:-mid_warehouse}"
  time_scale="${time_scale:-1}"
fi

root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${FLEET_BIN:-$root/build/bin}"
[ "$(id -u)" = 0 ] || { echo "netns.sh: needs root (ip netns, iptables)" >&2; exit 2; }
for tool in ip iptables tc; do
  command -v "$tool" > /dev/null || { echo "netns.sh: '$tool' missing; run scripts/install-deps" >&2; exit 2; }
done
[ -x "$bin/fleetctl" ] || { echo "netns.sh: $bin/fleetctl missing; build first (scripts/test builds)" >&2; exit 2; }

tag="fleet$$"   # unique per run, so two runs never share namespaces
hub="${tag}-hub"
hosts=("${tag}-srv")
for i in $(seq 1 "$agents"); do hosts+=("${tag}-a$i"); done
standby_args=()
if [ "$standby" = 1 ]; then
  hosts+=("${tag}-srv2")
  standby_args=(--standby --standby-wrap "ip netns exec ${tag}-srv2")
fi

cleanup() {
  for ns in "${hosts[@]}" "$hub"; do ip netns del "$ns" 2> /dev/null || true; done
}
trap cleanup EXIT

# shellcheck source=tests/soak/netns_hosts.sh
. "$root/tests/soak/netns_hosts.sh"
netns_hub "$hub"
n=1
for ns in "${hosts[@]}"; do
  netns_host "$hub" "$ns" "$n" "10.77.0.$((n + 1))"
  if [ "$ns" != "${hosts[0]}" ] && [ "$ns" != "${tag}-srv2" ]; then
    # Random loss both ways on every agent's link, and a 2 Mbit/s cap on what it sends.
    ip netns exec "$ns" iptables -A INPUT -i eth0 -m statistic --mode random --probability "$loss" -j DROP
    ip netns exec "$ns" iptables -A OUTPUT -o eth0 -m statistic --mode random --probability "$loss" -j DROP
    ip netns exec "$ns" tc qdisc add dev eth0 root tbf rate 2mbit burst 32kbit latency 50ms
  fi
  n=$((n + 1))
done

# Every host's link is up before DDS is asked to discover across them.
for ns in "${hosts[@]}"; do
  ip -n "$ns" link show eth0 | grep -q "state UP" || { echo "netns.sh: eth0 of $ns is not up" >&2; exit 1; }
done

export CYCLONEDDS_URI="file://$root/config/cyclonedds-compose.xml"
echo "netns.sh: server in ${hosts[0]}$([ "$standby" = 1 ] && echo ", standby in ${tag}-srv2")," \
  "$agents agents in ${tag}-a1..a$agents; ${loss} loss each way, 2 Mbit/s," \
  "poses 20 +- 10 ms late; soak on $site at time scale $time_scale for $duration s" >&2
set +e
ip netns exec "${hosts[0]}" "$bin/fleetctl" --domain 7 "${security[@]}" soak --agents "$agents" --site "$site" --duration "$duration" \
  --time-scale "$time_scale" --seed 7 --faults "$faults" "${standby_args[@]}" \
  --set faults.pose_delay_ms=20 --set faults.pose_delay_jitter_ms=10 \
  --agent-wrap "ip netns exec ${tag}-a{n}" "${verbose[@]}" --json > "${json_out:-/dev/stdout}"
status=$?
set -e
[ -n "$json_out" ] && cat "$json_out"
echo "netns.sh: soak exit status $status" >&2
exit $status

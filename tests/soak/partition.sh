#!/bin/bash
# Split brain: two servers on two hosts (network namespaces) and the link between them cut for
# 30 s while orders are placed on both sides, then healed. Server a (active) and two agents share
# one host; server b, its standby, has a host of its own. Cut off, b takes over in term 2 (its
# order ids from term 2's block) while a goes on with the robots; each takes orders. Healed, a
# hears b outrank it, steps down and hands over what it changed; b merges it. Then every order of
# both sides ends DONE exactly once, and one server is active.
#
# Everything stays inside the namespaces this script creates (10.78.0.0/24, names fleet<pid>-*);
# nothing touches the host's own interfaces or routes.
#
# usage (root): tests/soak/partition.sh [--cut S] [--domain N] [--keep]
# Exit 0 passed, 1 failed, 77 skipped (not root, or ip/iptables missing).
set -euo pipefail

cut_s=30
domain=78
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --cut) cut_s="$2"; shift 2 ;;
    --domain) domain="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "partition.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${FLEET_BIN:-$root/build/bin}"
if [ "$(id -u)" != 0 ]; then echo "partition.sh: skipped: needs root (ip netns, iptables)" >&2; exit 77; fi
for tool in ip iptables; do
  command -v "$tool" > /dev/null || { echo "partition.sh: skipped: '$tool' missing" >&2; exit 77; }
done
[ -x "$bin/fleetctl" ] || { echo "partition.sh: $bin/fleetctl missing; build first" >&2; exit 2; }

tag="fleet$$"
hub="${tag}-hub"
host_a="${tag}-a"
host_b="${tag}-b"
run_dir="$(mktemp -d /tmp/fleet-partition.XXXXXX)"
pids=()

cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  sleep 1
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2> /dev/null || true; done
  for ns in "$host_a" "$host_b" "$hub"; do ip netns del "$ns" 2> /dev/null || true; done
  [ "$keep" = 1 ] || rm -rf "$run_dir"
}
trap cleanup EXIT

fail() {
  echo "partition.sh: FAILED: $*" >&2
  for log in "$run_dir"/*.log; do
    echo "----- $(basename "$log") (last 40 lines)" >&2
    tail -n 40 "$log" >&2
  done
  exit 1
}

# shellcheck source=tests/soak/netns_hosts.sh
. "$root/tests/soak/netns_hosts.sh"
netns_hub "$hub"
netns_host "$hub" "$host_a" 1 10.78.0.2
netns_host "$hub" "$host_b" 2 10.78.0.3

export CYCLONEDDS_URI="file://$root/config/cyclonedds-compose.xml"
common=(--domain "$domain" --site table_a --time-scale 10)

# start NAME HOST COMMAND...: a process in a namespace, its log in the run directory.
start() {
  local name="$1" host="$2"
  shift 2
  ip netns exec "$host" "$@" > "$run_dir/$name.log" 2>&1 &
  pids+=($!)
}
# ctl HOST ARGS...: fleetctl on a host.
ctl() {
  local host="$1"
  shift
  ip netns exec "$host" "$bin/fleetctl" --domain "$domain" "$@"
}
# wait_for SECONDS WHAT COMMAND...: until the command succeeds.
wait_for() {
  local seconds="$1" what="$2"
  shift 2
  local until=$((SECONDS + seconds))
  until "$@" > /dev/null 2>&1; do
    [ "$SECONDS" -lt "$until" ] || fail "$what within $seconds s"
    sleep 0.5
  done
}
logged() { grep -q -- "$2" "$run_dir/$1.log"; }
robots_report() { ctl "$host_a" robots | grep -q fl2; }
# add HOST FROM TO: a transport order placed on HOST's side; prints its id.
add() {
  ctl "$1" --json order add --from "$2" --to "$3" | python3 -c 'import json, sys; print(json.load(sys.stdin)["order_id"])'
}
# state_of ID: the order's state as the active server publishes it, read from host a.
state_of() {
  ctl "$host_a" --json order show "$1" 2> /dev/null | python3 -c 'import json, sys; print(json.load(sys.stdin)["state"])'
}
all_done() {
  for id in "$@"; do [ "$(state_of "$id")" = DONE ] || return 1; done
}

start server-a "$host_a" "$bin/fleet-server" "${common[@]}" --db "$run_dir/a.db" --http-port 0 --set server.id=server-a
start server-b "$host_b" "$bin/fleet-server" "${common[@]}" --db "$run_dir/b.db" --http-port 0 --standby \
  --set server.id=server-b
start agent-fl1 "$host_a" "$bin/fleet-agent" --id fl1 "${common[@]}"
start agent-fl2 "$host_a" "$bin/fleet-agent" --id fl2 "${common[@]}"
wait_for 20 "server b hearing server a" logged server-b "the active server server-a is heard"
wait_for 30 "both robots reporting" robots_report

before=$(add "$host_a" A1 A2)
[ -n "$before" ] || fail "order A1 -> A2 not taken"
wait_for 90 "order $before done" all_done "$before"
sleep 2  # server b mirrors the pallet's new place

echo "partition.sh: cutting server b's host off for $cut_s s" >&2
# Each host drops what comes from the other; what a host's own processes say to each other
# (its multicast looped back included) goes on.
partition() {
  ip netns exec "$host_a" iptables "$1" INPUT -s 10.78.0.3 -j DROP
  ip netns exec "$host_b" iptables "$1" INPUT -s 10.78.0.2 -j DROP
}
partition -A
cut_at=$SECONDS
wait_for 20 "server b taking over" logged server-b "server-b in term 2"
side_a=("$(add "$host_a" A3 A4)" "$(add "$host_a" A7 A8)")
side_b=("$(add "$host_b" A5 A6)" "$(add "$host_b" A2 A1)")
for id in "${side_a[@]}" "${side_b[@]}"; do [ -n "$id" ] || fail "an order placed during the cut was not taken"; done
echo "partition.sh: orders on a's side ${side_a[*]}, on b's side ${side_b[*]}" >&2
for id in "${side_a[@]}"; do [ "$id" -lt 1000000 ] || fail "server a's order $id is not in term 1's block"; done
for id in "${side_b[@]}"; do [ "$id" -gt 1000000 ] || fail "server b's order $id is not in term 2's block"; done
sleep $((cut_s - (SECONDS - cut_at) > 0 ? cut_s - (SECONDS - cut_at) : 0))

echo "partition.sh: healing the link" >&2
partition -D
healed_at=$SECONDS
wait_for 60 "server a stepping down" logged server-a "stepping down"
echo "partition.sh: server a stepped down $((SECONDS - healed_at)) s after the heal" >&2
wait_for 150 "every order done" all_done "$before" "${side_a[@]}" "${side_b[@]}"

# Each order done once, by one robot.
for id in "$before" "${side_a[@]}" "${side_b[@]}"; do
  count=$(cat "$run_dir"/agent-*.log | grep -c "order $id done: " || true)
  [ "$count" = 1 ] || fail "order $id done $count times by the robots"
done
# One active server: b, with a its standby.
servers=$(ctl "$host_a" --json servers)
active=$(echo "$servers" | python3 -c 'import json, sys
print(",".join(s["server_id"] for s in json.load(sys.stdin)["servers"] if s["role"] == "active"))')
[ "$active" = server-b ] || fail "active servers '$active', not server b alone: $servers"
logged server-b "handed over by a server that stepped down" || fail "server b took no order over from server a"
echo "partition.sh: passed: ${#side_a[@]} orders on a's side and ${#side_b[@]} on b's side during a $cut_s s cut," \
  "all done once, one active server" >&2

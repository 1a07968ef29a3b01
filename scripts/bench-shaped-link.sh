#!/usr/bin/env bash
# Frame latency over a slow link, JPEG against H.264: a server and one dragging client (penumbra
# load, interactive frames, each asked for once the last has come) in a network namespace of their
# own whose loopback is shaped by tc netem (a delay each way, so the round trip is twice it, and a
# rate), run once with each encoding. Prints both reports and the ratios. Needs root (unshare -n,
# tc); changes nothing outside its namespace.
#
#   sudo bash scripts/bench-shaped-link.sh [--rate 10mbit] [--delay 20ms] [--seconds 20]
#        [--size 512] [--mode sbrc] [--volume ch2.nii.gz] [--data DIR] [--penumbra BIN]
set -euo pipefail

rate=10mbit
delay=20ms
seconds=20
size=512
mode=sbrc
volume=ch2.nii.gz
data=/usr/share/mricron/templates
penumbra=build/release/server/app/penumbra
while [[ $# -gt 0 ]]; do
  case "$1" in
    --rate) rate=$2; shift 2 ;;
    --delay) delay=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --mode) mode=$2; shift 2 ;;
    --volume) volume=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --penumbra) penumbra=$2; shift 2 ;;
    *) echo "bench-shaped-link: unknown option $1" >&2; exit 2 ;;
  esac
done
penumbra=$(realpath "$penumbra")
data=$(realpath "$data")

if [[ -z "${PENUMBRA_IN_SHAPED_NAMESPACE:-}" ]]; then
  exec env PENUMBRA_IN_SHAPED_NAMESPACE=1 unshare -n bash "$0" --rate "$rate" --delay "$delay" \
    --seconds "$seconds" --size "$size" --mode "$mode" --volume "$volume" --data "$data" \
    --penumbra "$penumbra"
fi

# Ethernet-sized packets: a token bucket drops any packet larger than its burst.
ip link set lo mtu 1500 up
if tc qdisc add dev lo root netem delay "$delay" rate "$rate" 2>/dev/null; then
  echo "link: loopback of a namespace of its own, netem delay $delay each way, rate $rate"
else
  # A kernel without sch_netem: the rate alone, through a token bucket.
  tc qdisc add dev lo root tbf rate "$rate" burst 16kb latency 400ms
  delay=0ms
  echo "link: loopback of a namespace of its own, rate $rate (tbf); this kernel has no netem," \
    "so no delay is added"
fi

log=$(mktemp)
"$penumbra" serve --port 0 --address 127.0.0.1 --data "$data" >"$log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; rm -f "$log"' EXIT
port=""
for _ in $(seq 1 600); do
  port=$(sed -n 's/^serving: *http:\/\/127\.0\.0\.1:\([0-9]*\)\/.*/\1/p' "$log")
  [[ -n "$port" ]] && break
  sleep 0.1
done
[[ -n "$port" ]] || { cat "$log" >&2; echo "bench-shaped-link: the server did not start" >&2; exit 1; }

run() {
  "$penumbra" load --port "$port" --clients 1 --seconds "$seconds" --volume "$volume" \
    --mode "$mode" --size "$size" --interactive --encoding "$1"
}
echo "== jpeg"
jpeg=$(run jpeg | tee /dev/stderr)
echo "== h264"
h264=$(run h264 | tee /dev/stderr)

# The figures the two reports share, side by side.
latency() { awk -v column="$2" '/^latency \(client\)/ { print $column }' <<<"$1"; }
per_frame() { sed -n 's/^frames:.*, \([0-9.]*\) KiB\/frame.*/\1/p' <<<"$1"; }
per_second() { sed -n 's/^frames: *[0-9]* (\([0-9.]*\) frames\/s).*/\1/p' <<<"$1"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "n/a" }'; }
echo "== jpeg / h264 (${size}x${size}, $mode, interactive; $delay each way, $rate)"
printf '%-18s %10s %10s %8s\n' "" jpeg h264 ratio
for row in "KiB/frame per_frame" "frames/s per_second" "latency-p50 3" "latency-p99 5"; do
  set -- $row
  if [[ "$2" =~ ^[0-9]+$ ]]; then
    a=$(latency "$jpeg" "$2"); b=$(latency "$h264" "$2")
  else
    a=$($2 "$jpeg"); b=$($2 "$h264")
  fi
  printf '%-18s %10s %10s %8s\n' "$1" "$a" "$b" "$(ratio "$a" "$b")"
done

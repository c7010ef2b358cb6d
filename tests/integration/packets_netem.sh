# Real packets across a link with a known delay: three network namespaces (sender, router, receiver)
# joined by veth pairs, `tc qdisc ... netem delay 20ms` on the router's link to the receiver, a
# sender of length-prefixed JSON commands over TCP and of datagrams over UDP at 100 Hz, and
# `m2mlat packets --interface` capturing live on both ends. Then `m2mlat packets SENDER --peer
# RECEIVER` must give every command's one-way time within 0.1 ms of what the two ends' clocks say
# (the kernel's socket timestamps: sent, received), and the median within 1 ms of netem's delay.
# The delay sits on the router, not on the sender's own interface: a capture on an interface sees
# its outgoing packets after that interface's queueing discipline, netem's delay included.
# Skipped (exit 77) where the kernel lacks network namespaces or netem. About 3 s.
source "$(dirname "$0")/lib.bash"
DELAY_MS=20
# M2MLAT_PACKETS_NO_NETEM=1 runs the same test without the delay (expected one-way: about 0 ms), to
# check the test itself on a kernel without netem.
NO_NETEM=${M2MLAT_PACKETS_NO_NETEM:-0}
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root (network namespaces)"; exit 77; }
command -v ip >/dev/null && command -v tc >/dev/null || { echo "SKIP: no ip or tc (apt-get install iproute2)"; exit 77; }
NS="m2mlat$$"
SND=${NS}s RTR=${NS}r RCV=${NS}v
remove_namespaces() { for n in "$SND" "$RTR" "$RCV"; do ip netns del "$n" 2>/dev/null || true; done; }
trap 'cleanup; remove_namespaces' EXIT
ip netns add "$SND" 2>ns.err || { echo "SKIP: no network namespaces here: $(cat ns.err)"; exit 77; }
ip netns add "$RTR"
ip netns add "$RCV"
ip link add s0 netns "$SND" type veth peer name r0 netns "$RTR"
ip link add r1 netns "$RTR" type veth peer name v0 netns "$RCV"
ip -n "$SND" addr add 10.201.1.1/24 dev s0
ip -n "$RTR" addr add 10.201.1.2/24 dev r0
ip -n "$RTR" addr add 10.201.2.1/24 dev r1
ip -n "$RCV" addr add 10.201.2.2/24 dev v0
for pair in "$SND s0" "$RTR r0" "$RTR r1" "$RCV v0" "$SND lo" "$RTR lo" "$RCV lo"; do
  set -- $pair
  ip -n "$1" link set "$2" up
done
ip -n "$SND" route add default via 10.201.1.2
ip -n "$RCV" route add default via 10.201.2.1
ip netns exec "$RTR" sysctl -qw net.ipv4.ip_forward=1
expected_ns=0
if [ "$NO_NETEM" != 1 ]; then
  ip netns exec "$RTR" tc qdisc add dev r1 root netem delay ${DELAY_MS}ms 2>tc.err ||
    { echo "SKIP: the kernel has no netem (sch_netem): $(cat tc.err)"; exit 77; }
  expected_ns=$((DELAY_MS * 1000000))
fi

# Live captures on both ends, each also written to a pcap file.
FILTER="(tcp port 7000 or udp port 7001) and host 10.201.1.1"
for side in "$SND s0 snd" "$RCV v0 rcv"; do
  set -- $side
  ip netns exec "$1" "$M2MLAT" packets --interface "$2" --filter "$FILTER" --key json:id --sender-ms stamp \
    --node "$3" --write "$3.pcap" --csv -o "$3.live.csv" 2>"$3.err" &
  PIDS+=($!)
done
for side in snd rcv; do
  for _ in $(seq 100); do grep -q "capturing on" "$side.err" 2>/dev/null && break; sleep 0.05; done
  grep -q "capturing on .* (timestamps: host)" "$side.err" || fail "$side capture did not start: $(cat "$side.err")"
done

# What the two ends' clocks say, each from the kernel's socket timestamps rather than from the
# capture: the receiver's CLOCK_REALTIME when the kernel received the segment or datagram that
# completed each command (SO_TIMESTAMPNS), the sender's when the kernel sent it (SO_TIMESTAMPING,
# software transmit stamps). Both programs write "id ns" lines.
ip netns exec "$RCV" $PY - <<'PYEOF' >recv.log 2>recv.err &
import json, socket, struct, threading
SO_TIMESTAMPNS = 35
out = []
lock = threading.Lock()
def stamp(ancillary):
    for level, kind, data in ancillary:
        if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS:
            sec, nsec = struct.unpack("qq", data[:16]); return sec * 1_000_000_000 + nsec
    raise SystemExit("no receive timestamp")
def note(body, t):
    with lock: out.append((json.loads(body)["id"], t))
tcp = socket.socket(); tcp.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
tcp.bind(("10.201.2.2", 7000)); tcp.listen(1)
udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); udp.bind(("10.201.2.2", 7001)); udp.settimeout(4)
udp.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
print("ready", flush=True)
def tcp_side():
    conn, _ = tcp.accept()
    conn.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    buf = b""
    while True:
        chunk, ancillary, _, _ = conn.recvmsg(65536, 256)
        if not chunk: break
        buf += chunk
        while len(buf) >= 4 and len(buf) >= 4 + struct.unpack(">I", buf[:4])[0]:
            n = struct.unpack(">I", buf[:4])[0]; note(buf[4:4 + n], stamp(ancillary)); buf = buf[4 + n:]
def udp_side():
    try:
        while True:
            data, ancillary, _, _ = udp.recvmsg(65536, 256)
            if data == b"end": break
            note(data, stamp(ancillary))
    except socket.timeout:
        pass
threads = [threading.Thread(target=tcp_side), threading.Thread(target=udp_side)]
for t in threads: t.start()
for t in threads: t.join()
for i, t in out: print(i, t)
PYEOF
PIDS+=($!)
for _ in $(seq 100); do grep -q ready recv.log 2>/dev/null && break; sleep 0.05; done

# The sender: 100 commands at 100 Hz on each transport, each carrying its send time in ms ("stamp").
ip netns exec "$SND" $PY - <<'PYEOF' >send.log
import json, select, socket, struct, time
SO_TIMESTAMPING = 37
# software transmit stamps, reported; one per send (OPT_ID), without the packet (OPT_TSONLY)
FLAGS = (1 << 1) | (1 << 4) | (1 << 7) | (1 << 11)
tcp = socket.create_connection(("10.201.2.2", 7000)); tcp.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
for s in (tcp, udp): s.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPING, FLAGS)
def sent_at(s):
    for _ in range(2):
        select.select([s], [], [], 1.0)  # the error queue makes the socket readable
        try:
            _, ancillary, _, _ = s.recvmsg(1, 512, socket.MSG_ERRQUEUE | socket.MSG_DONTWAIT)
        except BlockingIOError:
            continue
        for level, kind, data in ancillary:
            if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPING:
                sec, nsec = struct.unpack("qq", data[:16]); return sec * 1_000_000_000 + nsec
    raise SystemExit("no transmit timestamp")
start = time.monotonic()
for k in range(100):
    time.sleep(max(0, start + k * 0.01 - time.monotonic()))
    for proto in ("t", "u"):
        body = json.dumps({"id": f"{proto}{k}", "stamp": time.time_ns() // 1000000, "steer": 0.01 * k}).encode()
        if proto == "t": tcp.sendall(struct.pack(">I", len(body)) + body); print(f"{proto}{k}", sent_at(tcp))
        else: udp.sendto(body, ("10.201.2.2", 7001)); print(f"{proto}{k}", sent_at(udp))
time.sleep(0.1)
tcp.close()
udp.sendto(b"end", ("10.201.2.2", 7001))
PYEOF
wait "${PIDS[2]}" || fail "receiver failed: $(cat recv.err)"
sleep 0.2  # the captures see the last packets
kill -TERM "${PIDS[0]}" "${PIDS[1]}"
wait "${PIDS[0]}" || fail "sender's capture failed: $(cat snd.err)"
wait "${PIDS[1]}" || fail "receiver's capture failed: $(cat rcv.err)"
PIDS=()

# The files written while capturing, matched by key.
"$M2MLAT" packets snd.pcap --peer rcv.pcap --filter "$FILTER" --key json:id --sender-ms stamp --csv -o oneway.csv
"$M2MLAT" packets snd.pcap --peer rcv.pcap --filter "$FILTER" --key json:id --sender-ms stamp >oneway.txt
$PY - "$expected_ns" <<'PYEOF' || { tail -5 oneway.txt >&2; fail "one-way times"; }
import csv, statistics, sys
expected = int(sys.argv[1])
pairs = lambda f: dict(l.split() for l in open(f) if len(l.split()) == 2)
sent = pairs("send.log"); received = pairs("recv.log")
rows = list(csv.DictReader(l for l in open("oneway.csv") if not l.startswith("#")))
assert len(rows) == 200, f"{len(rows)} commands matched, expected 200"
assert set(r["key"] for r in rows) == set(sent), "the matched keys are not the commands sent"
worst = 0
for r in rows:
    app = int(received[r["key"]]) - int(sent[r["key"]])
    err = int(r["one_way_ns"]) - app
    worst = max(worst, abs(err))
    assert abs(err) <= 100_000, f"{r['key']}: capture one-way {r['one_way_ns']} ns, the two ends' clocks {app} ns"
    # The stamp is the sender's time in whole ms, taken before the send: at most 1 ms + the send before.
    assert 0 <= int(r["sender_to_sent_ns"]) < 2_000_000, f"{r['key']}: sender stamp to capture {r['sender_to_sent_ns']} ns"
median = statistics.median(int(r["one_way_ns"]) for r in rows)
assert abs(median - expected) <= 1_000_000, f"median one-way {median} ns, netem's delay {expected} ns"
print(f"200 commands, median one-way {median / 1e6:.3f} ms (netem {expected / 1e6:.0f} ms), "
      f"largest difference from the two ends' clocks {worst / 1e3:.1f} us")
PYEOF
grep -q "one-way: n 200, median" oneway.txt || fail "no summary line: $(cat oneway.txt)"
# The live markers (written as CSV at the end of each capture) are the files' markers.
[ "$(grep -c ',packet,' snd.live.csv)" = 200 ] || fail "sender's live markers: $(grep -c ',packet,' snd.live.csv)"
echo "packets_netem: ok"

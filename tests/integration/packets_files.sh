# `m2mlat packets` on capture files: two raw-IP pcap files with nanosecond timestamps (written here
# byte by byte, as tcpdump --time-stamp-precision=nano writes them) of the same UDP JSON commands,
# matched by key into exact one-way times; bad input (truncated file, unknown link type, missing
# file, bad rule) exits with the documented code and names the file and the packet.
source "$(dirname "$0")/lib.bash"
$PY - <<'PYEOF'
import json, struct
T0 = 1_764_000_000_000_000_000
def pcap(path, linktype, packets):
    with open(path, "wb") as f:
        f.write(struct.pack("<IHHiIII", 0xA1B23C4D, 2, 4, 0, 0, 65535, linktype))  # nanosecond magic
        for t, frame in packets:
            f.write(struct.pack("<IIII", t // 1_000_000_000, t % 1_000_000_000, len(frame), len(frame)))
            f.write(frame)
def udp_ip(payload, sport=40000, dport=7001):
    udp = struct.pack(">HHHH", sport, dport, 8 + len(payload), 0) + payload
    return struct.pack(">BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0x4000, 64, 17, 0,
                       bytes([10, 0, 0, 1]), bytes([10, 0, 0, 2])) + udp
cmds = [json.dumps({"seq": k, "stamp": T0 // 1_000_000 + 10 * k}).encode() for k in range(3)]
pcap("sender.pcap", 101, [(T0 + k * 10_000_000 + 250_000, udp_ip(c)) for k, c in enumerate(cmds)])
# The receiver sees command 1 first (reordered on the way), 2 never.
pcap("receiver.pcap", 101, [(T0 + 10_000_000 + 20_000_007, udp_ip(cmds[1])), (T0 + 20_123_456, udp_ip(cmds[0]))])
pcap("wifi.pcap", 105, [(T0, b"\0" * 40)])
# pcap's seconds are unsigned 32-bit: times from 2038-01-19 03:14:08 UTC to 2106.
LATE = [2**31 * 10**9 + 5, 4_200_000_000 * 10**9 + 123_456_789]
pcap("late.pcap", 101, [(t, udp_ip(json.dumps({"seq": k}).encode())) for k, t in enumerate(LATE)])
open("late.expected", "w").write(" ".join(map(str, LATE)))
PYEOF
"$M2MLAT" packets late.pcap --key json:seq --json | $PY -c '
import json, sys
d = json.load(sys.stdin)
times = " ".join(str(m["time_ns"]) for m in d["markers"])
assert times == open("late.expected").read(), times'
"$M2MLAT" packets sender.pcap --peer receiver.pcap --key json:seq --sender-ms stamp --csv -o oneway.csv
expected='key,sent_ns,received_ns,one_way_ns,one_way_ms,sender_ns,sender_to_sent_ns,sender_to_received_ns,sent_origin,received_origin
0,1764000000000250000,1764000000020123456,19873456,19.873456,1764000000000000000,250000,20123456,sender.pcap#1 udp 10.0.0.1:40000>10.0.0.2:7001,receiver.pcap#2 udp 10.0.0.1:40000>10.0.0.2:7001
1,1764000000010250000,1764000000030000007,19750007,19.750007,1764000000010000000,250000,20000007,sender.pcap#2 udp 10.0.0.1:40000>10.0.0.2:7001,receiver.pcap#1 udp 10.0.0.1:40000>10.0.0.2:7001'
[ "$(cat oneway.csv)" = "$expected" ] || fail "one-way CSV: $(cat oneway.csv)"
"$M2MLAT" packets sender.pcap --peer receiver.pcap --key json:seq >table.txt
grep -q "one-way: n 2, median 19.812 ms, p95 19.867 ms" table.txt || fail "summary: $(cat table.txt)"
grep -q "unmatched: 1 only in the sender's capture, 0 only in the receiver's" table.txt || fail "unmatched: $(cat table.txt)"
"$M2MLAT" packets sender.pcap --key json:seq --json | $PY -c '
import json, sys
d = json.load(sys.stdin)
assert d["format"] == "m2mlat-markers/1" and len(d["markers"]) == 3 and d["counts"]["packets"] == 3, d
assert d["markers"][2]["time_ns"] == 1764000000020250000 and d["markers"][2]["source"] == "file", d'
# Bad input: the third packet cut short; another link type; no such file; a bad rule or filter.
head -c -5 sender.pcap >cut.pcap
expect_exit 65 "$M2MLAT" packets cut.pcap --key json:seq
grep -q "cut.pcap: packet 3: cannot be read (truncated" err.txt || fail "truncation: $(cat err.txt)"
expect_exit 65 "$M2MLAT" packets wifi.pcap
grep -q "wifi.pcap: link type 105 IEEE802_11" err.txt || fail "link type: $(cat err.txt)"
expect_exit 66 "$M2MLAT" packets missing.pcap
expect_exit 2 "$M2MLAT" packets sender.pcap --key json
grep -q "key 'json'" err.txt || fail "bad key: $(cat err.txt)"
expect_exit 2 "$M2MLAT" packets sender.pcap --filter 'udp port x'
# A filter that passes nothing says so, with what the capture held; the summary comes first.
"$M2MLAT" packets sender.pcap --key json:seq --filter 'tcp port 7000' >none.txt 2>none.err
grep -q "the filter 'tcp port 7000' passed none of its 3 packets" none.err || fail "empty filter: $(cat none.err)"
head -1 table.txt | grep -q "^one-way: n 2" || fail "summary first: $(head -2 table.txt)"
expect_exit 2 "$M2MLAT" packets sender.pcap --interface lo
echo "packets_files: ok"

# Kernel logs with the clock faults a board makes that m2mlat's simulator does not: written from a
# clean pair of logs ("[ s.us] GPIO_<pin>_IRQ:<ns>" lines), one fault or several per copy.
#   python3 clock_faults.py IN_DIR OUT_DIR FAULT[,FAULT...] [SEED]
# IN_DIR holds operator.log and vehicle.log; OUT_DIR gets both, faulted, and faults.json (what was
# done: the lines whose events must be left out, as indices into the clean log, per board; the lines
# put before the clean log's first; the number of steps). Faults:
#   outlier:SIDE:WHERE      one line's realtime stamp from another clock (WHERE: first, middle, last,
#                           or a line index): a driver's line stamped by ktime_get_ns, or off by hours
#   printk:SIDE:WHERE       one line's printk stamp off by tens of thousands of seconds instead
#   boot:SIDE:K:KIND        the log starts at boot: K edges stamped before the first synchronisation
#                           (KIND epoch: a board without a real-time clock, counting from 1970;
#                           fakehw: a fake-hwclock time saved days before), then the run after it
#   step:SIDE:SIZE_NS:WHERE the realtime clock stepped by SIZE_NS before line WHERE (every later
#                           line moves by it; the printk stamps do not)
import json
import random
import re
import sys

LINE = re.compile(r"^\[\s*(\d+)\.(\d{6})\] (GPIO_\d+_IRQ):(\d+)$")


def read(path):
    out = []
    for line in open(path):
        m = LINE.match(line.strip())
        if m:
            out.append([int(m.group(1)) * 1_000_000 + int(m.group(2)), m.group(3), int(m.group(4))])
    return out


def write(path, lines):
    with open(path, "w") as f:
        for us, marker, ns in lines:
            f.write(f"[{us // 1_000_000:5d}.{us % 1_000_000:06d}] {marker}:{ns}\n")


def where(lines, text):
    named = {"first": 0, "middle": len(lines) // 2, "last": len(lines) - 1}
    return named[text] if text in named else int(text)


def main():
    src, dst, faults = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
    rng = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    logs = {side: read(f"{src}/{side}.log") for side in ("operator", "vehicle")}
    left_out = {side: [] for side in logs}
    prefix = {side: [] for side in logs}  # lines before the clean log's first (boot)
    for fault in faults:
        kind, side, *args = fault.split(":")
        lines = logs[side]
        if kind == "outlier":
            i = where(lines, args[0])
            # Another clock: monotonic ns (ktime_get_ns), or a clock hours off.
            lines[i][2] = lines[i][0] * 1000 + rng.randrange(0, 50_000) if rng.random() < 0.5 else \
                lines[i][2] - rng.choice([1, -1]) * rng.randrange(3_600, 90_000) * 1_000_000_000
            left_out[side].append(i)
        elif kind == "printk":
            i = where(lines, args[0])
            lines[i][0] += rng.randrange(10_000, 90_000) * 1_000_000
            left_out[side].append(i)
        elif kind == "step":
            size, i = int(args[0]), where(lines, args[1])
            for line in lines[i:]:
                line[2] += size
        elif kind == "boot":
            k, clock = int(args[0]), args[1]
            marker = lines[0][1]
            # Edges 3-30 s after boot, the clock set 45 s after boot; the run starts later.
            unset = -(lines[0][2] - lines[0][0] * 1000) if clock == "epoch" else -rng.randrange(2, 9) * 86_400 * 10**9
            us = 3_000_000
            for _ in range(k):
                us += rng.randrange(500_000, 3_000_000)
                ns = lines[0][2] - (lines[0][0] - us) * 1000 + unset - rng.randrange(2_000, 40_000) * 1000
                prefix[side].append([us, marker, ns])
        else:
            sys.exit(f"unknown fault {fault}")
    for side, lines in logs.items():
        write(f"{dst}/{side}.log", prefix[side] + lines)
    json.dump({"left_out": left_out, "prefix": {s: len(p) for s, p in prefix.items()},
               "steps": sum(f.startswith("step:") for f in faults)}, open(f"{dst}/faults.json", "w"))


main()

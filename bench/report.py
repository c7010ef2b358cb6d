#!/usr/bin/python3
"""Prints bench/run.sh's table from the results it left in one directory.

Usage: report.py WORK_DIR EVENTS_PER_SIDE BOOTSTRAP [--markdown]

WORK_DIR holds, for each program P in cli (m2mlat stats), lean (m2mlat_lean_stats) and baseline
(bench/baseline.py) and each bootstrap setting B in 0 and BOOTSTRAP: P-B.out (the program's JSON
output) and P-B.measure (bench/measure.py's wall seconds and peak memory); and micro.json (Google
Benchmark's JSON output of m2mlat_bench), rate.json (m2mlat_rate_bench's figures, if present) and
store.json (m2mlat_store_read_bench's, if present). One table: step, m2mlat figure, baseline figure, ratio,
and whether each target of issue 19 is met: `m2mlat stats` at least 10x faster than the baseline
without bootstrap and 20x with 2000 resamples (with fewer resamples the row says what it would need),
at no more than 40 % of its peak memory; the matcher within 1.2x of a plain merge of the same arrays; a
store of 10^8 events readable in seconds (opened, its sessions and counts, and one minute of one
channel read, within STORE_TARGET_S).
Exits with 1 if a micro-benchmark failed (a target not met is not a failure).
"""
import json
import os
import sys

SPEED_TARGET = 10.0  # m2mlat stats at least this many times faster than the baseline, no bootstrap
BOOTSTRAP_SPEED_TARGET = 20.0  # ... and this many times with BOOTSTRAP_TARGET_RESAMPLES resamples
BOOTSTRAP_TARGET_RESAMPLES = 2000  # the command line's default
MEMORY_TARGET = 0.4  # ... at no more than this multiple of the baseline's peak memory
MERGE_TARGET = 1.2  # pairing::match at most this multiple of a plain merge's time (same input)
STORE_TARGET_EVENTS = 100_000_000  # a store of this many events ...
STORE_TARGET_S = 10.0  # ... opened and its first minute of one channel read within this many seconds (wall)
# The steps of m2mlat_store_read_bench up to that first read.
STORE_FIRST_READ = ("open (read-only)", "sessions", "event_count of the store", "event_count of the session",
                    "channels of the session", "timestamps, one minute of one channel (first read)")


def load(path):
    with open(path) as f:
        return json.load(f)


def rate(x):
    for unit, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
        if x >= scale:
            return f"{x / scale:.3g} {unit}"
    return f"{x:.3g} "


def duration(value, unit):
    """Google Benchmark's time per iteration, in a readable unit."""
    seconds = value * {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[unit]
    if seconds >= 1:
        return f"{seconds:.2f} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds * 1e6:.3g} us"


def cli_summary(out):
    """n and median of `m2mlat stats --json` (m2mlat-stats/1)."""
    latency = out["scenarios"][0]["latency"]
    return latency["n"], latency["median_ms"]


class Table:
    def __init__(self):
        self.rows = []

    def section(self, title):
        self.rows.append((title,))

    def row(self, step, m2mlat, baseline="-", ratio="-", target="-"):
        self.rows.append((step, m2mlat, baseline, ratio, target))

    def text(self):
        header = ("step", "m2mlat", "baseline", "ratio", "target")
        cells = [header] + [r for r in self.rows if len(r) == 5]
        widths = [max(len(c[i]) for c in cells) for i in range(5)]

        def line(r):
            return "  ".join(c.ljust(w) if i in (0, 4) else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths)))

        out = [line(header)]
        for r in self.rows:
            if len(r) == 1:
                out += ["", f"== {r[0]} =="]
            else:
                out.append(line(r))
        return "\n".join(out)

    def markdown(self):
        out = ["| step | m2mlat | baseline | ratio | target |", "|---|---:|---:|---:|---|"]
        for r in self.rows:
            out.append(f"| **{r[0]}** | | | | |" if len(r) == 1 else "| " + " | ".join(r) + " |")
        return "\n".join(out)


def verdict(ok):
    return "met" if ok else "NOT MET"


def end_to_end(table, work, events, bootstrap):
    runs = {}
    for program in ("cli", "lean", "baseline"):
        for b in (0, bootstrap):
            runs[program, b] = (load(os.path.join(work, f"{program}-{b}.measure")),
                                load(os.path.join(work, f"{program}-{b}.out")))
    base_events = sum(runs["baseline", 0][1]["events"].values())
    table.section(f"end to end: import -> pair -> statistics of two kernel logs, ~{events:,} events per side "
                  f"({base_events:,} in all)")
    n_cli, median_cli = cli_summary(runs["cli", 0][1])
    base0 = runs["baseline", 0][1]
    table.row("latencies summarised (n; m2mlat leaves ambiguous pairs out)", f"{n_cli:,}", f"{base0['n']:,}")
    table.row("median latency, ms", f"{median_cli:.3f}", f"{base0['median']:.3f}")
    for program, name in (("cli", "m2mlat stats"), ("lean", "library, lean path")):
        for b in sorted({0, bootstrap}):
            m, _ = runs[program, b]
            base, _ = runs["baseline", b]
            what = f"{name}, bootstrap {b}" if b else f"{name}, no bootstrap"
            speedup = base["wall_s"] / m["wall_s"]
            mark = program == "cli"
            if b == 0:
                target = f"(>= {SPEED_TARGET:g}x)"
                judged = verdict(speedup >= SPEED_TARGET)
            else:
                target = f"(>= {BOOTSTRAP_SPEED_TARGET:g}x at {BOOTSTRAP_TARGET_RESAMPLES} resamples)"
                judged = (verdict(speedup >= BOOTSTRAP_SPEED_TARGET) if b == BOOTSTRAP_TARGET_RESAMPLES
                          else f"judged with --bootstrap {BOOTSTRAP_TARGET_RESAMPLES}")
            table.row(f"{what}: wall time", f"{m['wall_s']:.2f} s ({rate(base_events / m['wall_s'])}ev/s)",
                      f"{base['wall_s']:.2f} s ({rate(base_events / base['wall_s'])}ev/s)",
                      f"speed-up {speedup:.2f}x",
                      (judged if mark else "(library)") + " " + target)
            memory = m["peak_mib"] / base["peak_mib"]
            table.row(f"{what}: peak memory", f"{m['peak_mib']:.0f} MiB", f"{base['peak_mib']:.0f} MiB",
                      f"memory {memory:.2f}x",
                      (verdict(memory <= MEMORY_TARGET) if mark else "(library)") + f" (<= {MEMORY_TARGET:g}x)")
    # Per step: both programs time their own steps (the lean path and the baseline, same input).
    lean, base = runs["lean", bootstrap][1], runs["baseline", bootstrap][1]
    lines = sum(base["events"].values())
    table.section(f"per step (library lean path vs baseline, bootstrap {bootstrap}, their own timers)")
    lt, bt = lean["timing_s"], base["timing_s"]
    steps = (("import kernel logs (lines/s)", lt["import"], bt["import"], lines),
             ("pair (events/s, both sides)", lt["pair"], bt["pair"], lines),
             (f"statistics incl. bootstrap {bootstrap} (latencies/s)", lt["statistics"],
              bt["statistics"] + bt["bootstrap"], base["n"]))
    for step, mine, theirs, items in steps:
        table.row(step, f"{mine:.2f} s ({rate(items / mine)}/s)", f"{theirs:.2f} s ({rate(items / theirs)}/s)",
                  f"speed-up {theirs / mine:.2f}x")


def micro(table, path):
    """Adds the micro-benchmarks' rows; returns the number of cases that failed."""
    report = load(path)
    failed = 0
    table.section("micro-benchmarks (m2mlat_bench, wall-clock time; events count both sides)")
    for b in report["benchmarks"]:
        name = b["name"].removesuffix("/real_time")
        if b.get("error_occurred"):
            table.row(name, "error: " + b.get("error_message", ""))
            failed += 1
            continue
        unit = b.get("label", "items")
        table.row(name, f"{rate(b['items_per_second'])}{unit}/s ({duration(b['real_time'], b['time_unit'])})")
    floor(table, report["benchmarks"])
    return failed


def floor(table, benchmarks):
    """The matcher against a plain merge of the same two arrays, at each size both ran."""
    times = {b["name"].removesuffix("/real_time"): b["real_time"] for b in benchmarks if not b.get("error_occurred")}
    sizes = [name.rsplit(":", 1)[1] for name in times if name.startswith("pairing/merge_floor/")]
    if sizes:
        table.section("pairing against its floor (a plain sorted merge of the same two arrays)")
    for n in sizes:
        match, merge = times.get(f"pairing/match/events_per_side:{n}"), times[f"pairing/merge_floor/events_per_side:{n}"]
        if match is None:
            continue
        ratio = match / merge
        table.row(f"pairing/match vs merge, {int(n):,} events per side", f"{ratio:.1f}x the merge's time", "-",
                  f"{ratio:.1f}x", verdict(ratio <= MERGE_TARGET) + f" (<= {MERGE_TARGET:g}x)")
        # The floor of a matcher that weighs every candidate in the window (bench_pairing.cpp): the
        # matcher runs three passes; no target, the figure says how far it is from that floor.
        dp = times.get(f"pairing/window_dp_floor/events_per_side:{n}")
        if dp is not None:
            table.row(f"pairing/match vs 3 passes of the least window DP, {int(n):,} a side",
                      f"one pass {dp / merge:.1f}x the merge's time", "-", f"{match / (3 * dp):.1f}x")


def high_rate(table, r):
    """m2mlat_rate_bench: a gyroscope stream through the store, per sample."""
    samples = 2 * r["samples_per_side"]
    table.section(f"high-rate stream: {r['rate_hz']} Hz for {r['seconds']} s on each of two boards "
                  f"({r['samples_per_side']:,} samples a side), appended to the store, read back")
    table.row("on disk (store files after close)", f"{r['bytes'] / samples:.2f} bytes/sample ({r['bytes'] / 1e6:.0f} MB)")
    table.row("append, one transaction a second", f"{r['append_cpu_s'] / samples * 1e9:.0f} ns CPU/sample "
              f"({r['append_cpu_s']:.2f} s CPU, {r['append_wall_s']:.2f} s wall)")
    table.row("read back whole (Store::rate_trace)", f"{r['read_cpu_s'] / samples * 1e9:.0f} ns CPU/sample "
              f"({r['read_cpu_s']:.2f} s CPU, {r['read_wall_s']:.2f} s wall)")
    table.row("peak memory", f"{r['peak_mib']} MiB")


def big_store(table, r):
    """m2mlat_store_read_bench: a store appended, reopened and read as an analysis reads it."""
    steps = {s["what"]: s for s in r["steps"]}
    total = r["events"]
    table.section(f"a store of {total:,} events ({r['bytes'] / 1e9:.2f} GB), reopened and read")
    if "append" in r:
        a = r["append"]
        table.row("append, batches of 512", f"{a['cpu_s'] / total * 1e6:.2f} us CPU/event ({a['cpu_s']:.0f} s CPU, "
                  f"{a['wall_s']:.0f} s wall)")
    for s in r["steps"]:
        table.row(s["what"], f"{s['wall_s']:.3f} s wall, {s['cpu_s']:.3f} s CPU, peak {s['peak_mib']} MiB")
    first = sum(steps[w]["wall_s"] for w in STORE_FIRST_READ)
    judged = (verdict(first <= STORE_TARGET_S) if total >= STORE_TARGET_EVENTS
              else f"judged at {STORE_TARGET_EVENTS:,} events")
    table.row("opened to its first minute of one channel read", f"{first:.2f} s wall", "-", "-",
              f"{judged} (<= {STORE_TARGET_S:g} s at {STORE_TARGET_EVENTS:,} events)")


def main():
    args = [a for a in sys.argv[1:] if a != "--markdown"]
    if len(args) != 3:
        sys.exit(__doc__)
    work, events, bootstrap = args[0], int(args[1]), int(args[2])
    table = Table()
    end_to_end(table, work, events, bootstrap)
    failed = micro(table, os.path.join(work, "micro.json"))
    if os.path.exists(os.path.join(work, "rate.json")):
        high_rate(table, load(os.path.join(work, "rate.json")))
    if os.path.exists(os.path.join(work, "store.json")):
        big_store(table, load(os.path.join(work, "store.json")))
    print(table.markdown() if "--markdown" in sys.argv else table.text())
    print("\nspeed-up = baseline's wall time / m2mlat's; memory = m2mlat's peak resident memory / the baseline's. "
          f"Targets (issue 19), for `m2mlat stats`: speed-up >= {SPEED_TARGET:g}x without bootstrap and "
          f">= {BOOTSTRAP_SPEED_TARGET:g}x with {BOOTSTRAP_TARGET_RESAMPLES} resamples, at memory <= {MEMORY_TARGET:g}x; "
          f"pairing/match <= {MERGE_TARGET:g}x a plain merge's time; a store of {STORE_TARGET_EVENTS:,} events "
          f"opened and its first minute of one channel read in <= {STORE_TARGET_S:g} s.")
    context = load(os.path.join(work, "micro.json"))["context"]
    load_avg = ", ".join(f"{x:.2f}" for x in context.get("load_avg", []))
    print(f"\nmachine: {context['num_cpus']} CPUs at {context['mhz_per_cpu']} MHz, load average {load_avg} "
          f"(when the micro-benchmarks started), {context['date']}")
    if failed:
        sys.exit(f"report.py: {failed} micro-benchmark(s) failed")


if __name__ == "__main__":
    main()

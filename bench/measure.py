#!/usr/bin/python3
"""Runs a command and prints its wall time (s), CPU time (s, user + system) and peak resident memory
(MiB) as JSON, the command's own output going to a file. On a machine shared with other jobs the CPU
time varies much less than the wall time. Usage: measure.py OUTPUT_FILE -- COMMAND [ARGS...]"""
import json
import resource
import subprocess
import sys
import time

out, sep, *command = sys.argv[1:]
assert sep == "--", __doc__
start = time.monotonic()
with open(out, "w") as sink:
    code = subprocess.call(command, stdout=sink)
wall = time.monotonic() - start
usage = resource.getrusage(resource.RUSAGE_CHILDREN)
cpu = usage.ru_utime + usage.ru_stime
print(json.dumps({"exit": code, "wall_s": round(wall, 3), "cpu_s": round(cpu, 3),
                  "peak_mib": round(usage.ru_maxrss / 1024, 1)}))
sys.exit(code)

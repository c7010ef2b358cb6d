#!/usr/bin/python3
"""Runs a command and prints its wall time (s) and peak resident memory (MiB) as JSON, the
command's own output going to a file. Usage: measure.py OUTPUT_FILE -- COMMAND [ARGS...]"""
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
peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
print(json.dumps({"exit": code, "wall_s": round(wall, 3), "peak_mib": round(peak_kib / 1024, 1)}))
sys.exit(code)

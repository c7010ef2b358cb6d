# Every command of the README's shell blocks, as written, in order, from an empty folder (with the
# repository's docs/ and tests/ beside it, as in a checkout): the tour must work for a new user who
# has nothing but this repository. Commands that need a board (GPIO chips, an I2C gyroscope, the
# other board's store, an agent's config) must get as far as looking for it: they exit 66 (missing
# input) here, never 2 (a usage error: a flag the command does not know). `doctor` exits 1 on a
# machine that is not a prepared board; `schedtest --core 2` names the missing CPU on a machine with
# fewer than three (and is skipped on one with more: a minute of cyclictest). `make demo` and
# `make check` are not run here: `make check` is what runs this test.
source "$(dirname "$0")/lib.bash"
ROOT=$(realpath "$DATA/../..")
ln -s "$ROOT/docs" docs
ln -s "$ROOT/tests" tests
$PY - "$ROOT/README.md" "$M2MLAT" <<'PY'
import os, re, shlex, subprocess, sys, time

readme, m2mlat = sys.argv[1], sys.argv[2]
# The exit code a command gives on a machine without the rig, by the first pattern that matches it
# (default 0), with why.
BOARD = [
    (r"^m2mlat doctor\b", 1, "checks a board: fails its checks here"),
    (r"^m2mlat (record|pulse|led)\b", 66, "opens a GPIO chip"),
    (r"^m2mlat gyro\b", 66, "opens an I2C gyroscope"),
    (r"^m2mlat import wheel-gyro\.csv\b", 66, "reads the trace `m2mlat gyro` records on a board"),
    (r"^m2mlat agent\b", 66, "reads a board's agent configuration"),
    (r"^m2mlat collect\b", 66, "reads the agents' token file"),
    (r"^m2mlat (merge|synctest) campaign\.db operator\.db|^m2mlat synctest operator\.db", 66,
     "reads the boards' stores"),
    (r"^m2mlat budget --synctest sync\.json", 66, "reads a synchronisation test's result"),
    (r"^m2mlat packets operator\.pcap\b", 66, "reads the boards' packet captures"),
    (r"^m2mlat bag station\.mcap\b", 66, "reads a ROS 2 bag the stack recorded"),
    (r"^m2mlat schedtest --core 2\b", 2, "this machine has no CPU 2"),
]
SKIP = [
    (r"^make ", lambda: True, "the two commands: make check runs this test"),
    (r"^m2mlat schedtest\b", lambda: os.cpu_count() >= 3, "a 60 s cyclictest run"),
]

def commands(text):
    """The README's commands: the lines of its ```sh blocks, continuations joined, comments cut."""
    out, block, line_no = [], False, 0
    pending, start = "", 0
    for number, line in enumerate(text.splitlines(), 1):
        if line.startswith("```"):
            block = line.strip() == "```sh" and not block
            continue
        if not block:
            continue
        if not pending:
            start = number
        pending += line
        if pending.endswith("\\"):
            pending = pending[:-1] + " "
            continue
        command = re.split(r"\s#", " " + pending, maxsplit=1)[0].strip()
        pending = ""
        if command and not command.startswith("#") and command != "m=build/m2mlat":
            out.append((start, command))
    return out

failures, ran = [], 0
for number, command in commands(open(readme).read()):
    words = shlex.split(command)
    if words[0] == "sudo":
        words = words[1:]
    if words[0] == "$m":
        words[0] = "m2mlat"
    shown = " ".join(words)
    skip = next((why for pattern, when, why in SKIP if re.search(pattern, shown) and when()), None)
    if skip:
        print(f"skipped README.md:{number}: {shown} ({skip})")
        continue
    if words[0] != "m2mlat":
        failures.append(f"README.md:{number}: not an m2mlat command: {command}")
        continue
    want, why = next(((code, why) for pattern, code, why in BOARD if re.search(pattern, shown)), (0, ""))
    began = time.monotonic()
    run = subprocess.run([m2mlat] + words[1:], capture_output=True, text=True, timeout=300)
    ran += 1
    took = time.monotonic() - began
    print(f"README.md:{number}: exit {run.returncode} in {took:.1f} s: {shown[:100]}")
    if run.returncode != want:
        failures.append(f"README.md:{number}: `{shown}` exited {run.returncode}, expected {want}"
                        f"{' (' + why + ')' if why else ''}:\n{run.stderr[-2000:]}")
if ran < 30:
    failures.append(f"only {ran} commands found in the README's shell blocks")
if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
print(f"readme commands: {ran} ok")
PY

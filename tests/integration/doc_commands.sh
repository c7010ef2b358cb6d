# Every command of the README's and the docs' shell blocks, as written, in order, from one empty
# folder (with the repository's docs/ and tests/ beside it, as in a checkout): the README's tour
# first, then docs/*.md by name, so that a page may use what the tour made (campaign.db, loop.db).
# docs/field-guide.md is left out: tests/integration/field_guide.sh runs its commands on two
# stand-in boards. A block is run if its fence says ```sh; output samples and configuration files
# take another language (```text, ```ini, ```toml). A line may continue with "\", end with a
# "# comment", or open a here-document.
# Commands that need a board (GPIO chips, an I2C gyroscope, the other board's store, an agent's
# config) must get as far as looking for it: they exit 66 (missing input) here, never 2 (a usage
# error: a flag the command does not know). `doctor` exits 1 on a machine that is not a prepared
# board; `schedtest --core 2` names the missing CPU on a machine with fewer than three (and is
# skipped on one with more: a minute of cyclictest). Commands that need a server, root, a network
# interface or QEMU are in SKIP, each with its reason; any other command that is not m2mlat fails
# the test, so that a new one gets a reason or a run.
source "$(dirname "$0")/lib.bash"
ROOT=$(realpath "$DATA/../..")
ln -s "$ROOT/docs" docs
ln -s "$ROOT/tests" tests
$PY - "$ROOT" "$M2MLAT" <<'PY'
import glob, os, re, shlex, subprocess, sys, time

root, m2mlat = sys.argv[1], sys.argv[2]
PAGES = ["README.md"] + sorted(os.path.relpath(p, root) for p in glob.glob(f"{root}/docs/*.md")
                               if not p.endswith("/field-guide.md"))
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
    (r"^m2mlat bag (station|vehicle)\.mcap\b", 66, "reads a ROS 2 bag the stack recorded"),
    (r"^m2mlat schedtest --core 2\b", 2, "this machine has no CPU 2"),
    (r"^m2mlat report Static_Wifi\.csv Static_5G\.csv", 66, "the reference study's own paired CSVs"),
    (r"^m2mlat mark ", 74, "no agent's marker port listens here: mark says its mark is lost"),
]
ALWAYS = lambda: True
SKIP = [
    (r"^make ", ALWAYS, "the README's two commands and make check-vm: make check runs this test"),
    (r"(^|\s)tests/vm/", ALWAYS, "the real-kernel suite under QEMU: minutes; make check-vm runs it"),
    (r"^m2mlat schedtest\b", lambda: os.cpu_count() >= 3, "a 60 s cyclictest run"),
    (r"^m2mlat agent --source sim\b", ALWAYS, "a server that runs until stopped (agent_api.sh runs it)"),
    (r"^curl ", ALWAYS, "asks a running agent (agent_api.sh makes these requests)"),
    (r"^m2mlat collect --agent http://127\.0\.0\.1:8470 --store campaign\.db --duration 2s|"
     r"^python3 -c .*http://127\.0\.0\.1:8470/v1/status", ALWAYS,
     "asks or pulls the simulated agent the block starts (markers_agent.sh does the same)"),
    (r"^openssl ", ALWAYS, "makes the TLS example's secret; no m2mlat in it"),
    (r"postgresql://|^PGHOST=|--url-file", ALWAYS,
     "needs the lab's PostgreSQL server (archive_roundtrip.sh runs push, list, stats, report on its own)"),
    (r"^tcpdump |^m2mlat packets --interface", ALWAYS, "captures on a network interface, as root"),
    (r"^(modprobe|ls -l /dev/i2c|apt install|i2cdetect|i2cget|groupadd|tee /etc/|udevadm|usermod)\b", ALWAYS,
     "prepares a board, as root (docs/hardware.md)"),
]

def commands(text):
    """A page's commands: the lines of its ```sh blocks, continuations joined, comments cut, a
    here-document's lines kept with the command that opens it."""
    out, block = [], False
    pending, start, heredoc = "", 0, None
    for number, line in enumerate(text.splitlines(), 1):
        if heredoc is not None:
            pending += "\n" + line
            if line.strip() == heredoc:
                out.append((start, pending))
                pending, heredoc = "", None
            continue
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
        if (opened := re.search(r"<<-?'?(\w+)'?", command)):
            pending, heredoc = command, opened.group(1)
            continue
        pending = ""
        if command and not command.startswith("#") and command != "m=build/m2mlat":
            out.append((start, command))
    return out

failures, ran, per_page = [], 0, {}
for page in PAGES:
    for number, command in commands(open(os.path.join(root, page)).read()):
        where = f"{page}:{number}"
        first = command.split("\n", 1)[0]
        words = first.split() if "\n" in command else shlex.split(command)
        if words[0] == "sudo":
            words = words[1:]
        if words[0] == "$m":
            words[0] = "m2mlat"
        shown = " ".join(words)
        skip = next((why for pattern, when, why in SKIP if re.search(pattern, shown) and when()), None)
        if skip:
            print(f"skipped {where}: {shown[:100]} ({skip})")
            continue
        if words[0] != "m2mlat" or "\n" in command:
            failures.append(f"{where}: not an m2mlat command (run it, or give SKIP a reason): {first}")
            continue
        want, why = next(((code, why) for pattern, code, why in BOARD if re.search(pattern, shown)), (0, ""))
        began = time.monotonic()
        run = subprocess.run([m2mlat] + words[1:], capture_output=True, text=True, timeout=300)
        ran += 1
        per_page[page] = per_page.get(page, 0) + 1
        took = time.monotonic() - began
        print(f"{where}: exit {run.returncode} in {took:.1f} s: {shown[:100]}")
        if run.returncode != want:
            failures.append(f"{where}: `{shown}` exited {run.returncode}, expected {want}"
                            f"{' (' + why + ')' if why else ''}:\n{run.stderr[-2000:]}")
if per_page.get("README.md", 0) < 30:
    failures.append(f"only {per_page.get('README.md', 0)} commands found in the README's shell blocks")
if sum(n for page, n in per_page.items() if page != "README.md") < 15:
    failures.append(f"only {per_page} commands run from the docs' shell blocks")
if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
print(f"doc commands: {ran} ok ({', '.join(f'{p} {n}' for p, n in per_page.items())})")
PY

# Output files are written only over regular files (never through a symlink, never over a device,
# a FIFO or a directory), through a temporary that a planted file cannot redirect; and names from
# input reach the terminal with their control characters escaped.
source "$(dirname "$0")/lib.bash"
cp "$DATA/rig_paired_small.csv" run.csv
"$M2MLAT" import --store s.db run.csv > /dev/null 2>&1
"$M2MLAT" export s.db -o - > expected.csv
printf 'precious\n' > victim

# expect_refused WHAT TARGET command...: exit 74, a message naming the target and what it is.
expect_refused() {
  local what=$1 target=$2; shift 2
  expect_exit 74 timeout 20 "$@"
  grep -qF "$target: refusing to replace it: it is $what" err.txt || fail "'$*': message: $(cat err.txt)"
}

# A device: as root the old rename turned /dev/null into a regular file.
expect_refused "a character device" /dev/null "$M2MLAT" export s.db -o /dev/null
[ -c /dev/null ] || fail "/dev/null is no longer a character device"
expect_refused "a character device" /dev/null "$M2MLAT" pair s.db -o /dev/null
expect_refused "a character device" /dev/null "$M2MLAT" report s.db --html /dev/null
[ -c /dev/null ] || fail "/dev/null is no longer a character device"

# A symlink as the target: refused, the link and its target untouched.
ln -s victim link.csv
expect_refused "a symbolic link" link.csv "$M2MLAT" export s.db -o link.csv
expect_refused "a symbolic link" link.csv "$M2MLAT" pair s.db -o link.csv
expect_refused "a symbolic link" link.csv "$M2MLAT" pair s.db -o pairs.csv --unmatched link.csv
mkdir -p rep && ln -s ../victim rep/report.html
expect_refused "a symbolic link" rep/report.html "$M2MLAT" report s.db --out rep
[ -L link.csv ] && [ -L rep/report.html ] || fail "a link was replaced"
[ "$(cat victim)" = precious ] || fail "written through a symlink"

# A FIFO (nobody reads it: the command must not block on it) and a directory.
mkfifo fifo
expect_refused "a FIFO" fifo "$M2MLAT" export s.db -o fifo
expect_refused "a FIFO" fifo "$M2MLAT" report s.db --html fifo
[ -p fifo ] || fail "the FIFO was replaced"
mkdir dir
expect_refused "a directory" dir "$M2MLAT" export s.db -o dir

# The command's own store as its output: refused, the store intact.
expect_refused "an input of this command" s.db "$M2MLAT" export s.db -o s.db
"$M2MLAT" export s.db -o - | cmp -s - expected.csv || fail "the store changed after export -o STORE"

# The old temporary name "<target>.tmp", planted as a link, is not followed.
ln -s victim out.csv.tmp
"$M2MLAT" export s.db -o out.csv
cmp -s out.csv expected.csv || fail "out.csv differs from the export to stdout"
[ "$(cat victim)" = precious ] && [ -L out.csv.tmp ] || fail "written through out.csv.tmp"
# A regular file is replaced and keeps its mode.
chmod 600 out.csv
"$M2MLAT" export s.db -o out.csv
[ "$(stat -c %a out.csv)" = 600 ] || fail "mode of the replaced file: $(stat -c %a out.csv)"
# A missing folder is named.
expect_exit 74 "$M2MLAT" export s.db -o no/such/out.csv
grep -qF "no/such/out.csv: cannot create a file in no/such/: No such file or directory" err.txt ||
  fail "missing folder: $(cat err.txt)"
# simulate --out-dir: a file planted in the folder is not written through; a node name cannot lead
# the file out of the folder.
mkdir sim && ln -s ../victim sim/operator.log
expect_refused "a symbolic link" sim/operator.log \
  "$M2MLAT" simulate --out-dir sim --format kernel-log --manoeuvres 3
[ ! -e sim/vehicle.log ] || fail "vehicle.log written although operator.log was refused"
expect_exit 2 "$M2MLAT" simulate --out-dir sim2 --manoeuvres 3 --set cause_node=../escaped
[ ! -e escaped.csv ] && [ ! -e sim2 ] || fail "simulate wrote outside its folder"
[ "$(cat victim)" = precious ] || fail "written through a symlink"
# No temporary is left behind by any of the above.
leftover=$(find . -name '.*.tmp')
[ -z "$leftover" ] || fail "temporaries left behind: $leftover"

# A node name with an ESC sequence and a newline, and a scenario name with a window-title change:
# shown escaped by every terminal command; JSON escapes them its own way.
printf 'GPIO_16_IRQ:1700000000000000000\nGPIO_16_IRQ:1700000004000000000\n' > cause.log
printf 'GPIO_16_IRQ:1700000000800000000\nGPIO_16_IRQ:1700000004850000000\n' > effect.log
node=$'op\e[31m\nfake'
scenario=$'s1\e]0;owned\a'
"$M2MLAT" import --store n.db cause.log --node "$node" --role cause --scenario "$scenario" > import.txt
"$M2MLAT" import --store n.db effect.log --node vehicle --role effect --scenario "$scenario" >> import.txt
"$M2MLAT" stats n.db --bootstrap 0 --detail > stats.txt
"$M2MLAT" pair n.db > pair.txt
"$M2MLAT" report n.db > report.txt
"$M2MLAT" report n.db --print markdown > report.md.txt
for f in import.txt stats.txt pair.txt report.txt report.md.txt; do
  if grep -q $'[\e\a]' "$f"; then fail "$f holds a raw control character: $(cat -A "$f")"; fi
done
for f in stats.txt pair.txt report.txt; do
  grep -qF 'op\x1b[31m\nfake/gpio16' "$f" || fail "$f does not show the node escaped: $(cat "$f")"
  grep -qF 's1\x1b]0;owned\x07' "$f" || fail "$f does not show the scenario escaped: $(cat "$f")"
done
grep -qF "2 events of op\\x1b[31m\\nfake (cause) -> scenario 's1\\x1b]0;owned\\x07'" import.txt ||
  fail "import summary: $(cat import.txt)"
grep -qF 'scenario s1\x1b]0;owned\x07: op\x1b[31m\nfake/gpio16 -> vehicle/gpio16' stats.txt ||
  fail "stats --detail heading: $(cat stats.txt)"
"$M2MLAT" stats n.db --bootstrap 0 --json > stats.json
grep -qF 'op\u001b[31m\nfake' stats.json || fail "JSON escaping: $(cat stats.json)"
# A name that is not UTF-8: escaped on the terminal, U+FFFD in JSON (it used to end in exit 70).
"$M2MLAT" import --store u.db cause.log --node $'op\xffx' --role cause --scenario s2 > /dev/null
"$M2MLAT" import --store u.db effect.log --node vehicle --role effect --scenario s2 > /dev/null
"$M2MLAT" stats u.db --bootstrap 0 | grep -qF 'op\xffx/gpio16' || fail "invalid UTF-8 not escaped"
"$M2MLAT" stats u.db --bootstrap 0 --json | grep -qF "op"$'\xef\xbf\xbd'"x/gpio16" || fail "no U+FFFD in JSON"
"$M2MLAT" report u.db --out u-report > /dev/null
[ -s u-report/report.json ] && [ -s u-report/comparisons.csv ] || fail "report --out incomplete"
# Error messages quoting input are escaped too.
expect_exit 66 "$M2MLAT" import --store n.db $'no\e[2Jsuch.csv'
if grep -q $'\e' err.txt; then fail "raw ESC in the error: $(cat -A err.txt)"; fi
grep -qF 'no\x1b[2Jsuch.csv' err.txt || fail "error does not show the name escaped: $(cat err.txt)"
echo "1 passed, 0 failed"

# Damaged and foreign store files through the real commands: a store without its events table, a
# row that breaks the schema's rules (CHECKs switched off by another tool), a non-database, a
# directory and a FIFO are each refused with exit 65 and a message naming the file and what is
# wrong; a merge of a bad board store leaves the campaign store unchanged.
source "$(dirname "$0")/lib.bash"

"$M2MLAT" simulate --seed 3 --manoeuvres 20 --store good.db > /dev/null
[ "$(sqlite3 good.db 'select count(*) > 10 from events')" = 1 ] || fail "the simulated store is empty"
"$M2MLAT" stats good.db > /dev/null

# No events table: a data error naming the file and the table (was: exit 70 from a failed statement).
cp good.db no-events.db
sqlite3 no-events.db 'drop table events'
for cmd in "stats no-events.db" "export no-events.db" "merge camp.db no-events.db"; do
  expect_exit 65 $M2MLAT $cmd
  grep -q "no-events.db: damaged m2mlat store (schema version [0-9]*): table 'events' is missing" err.txt ||
    { cat err.txt >&2; fail "$cmd: no clear message"; }
done

# A row that breaks a CHECK: refused naming table, row and field (was: left out of the analysis).
cp good.db bad-edge.db
sqlite3 bad-edge.db 'pragma ignore_check_constraints = on; update events set edge = 2 where seq = 5'
expect_exit 65 "$M2MLAT" stats bad-edge.db
grep -q "bad-edge.db: table 'events' row seq 5: field 'edge' holds 2 (expected 0 or 1)" err.txt ||
  { cat err.txt >&2; fail "stats: no clear message for a bad row"; }
expect_exit 65 "$M2MLAT" export bad-edge.db
# merge: refused, and the campaign store keeps what it had (nothing of the bad board).
"$M2MLAT" merge camp.db good.db > /dev/null
before=$(sqlite3 camp.db 'select count(*) from events')
expect_exit 65 "$M2MLAT" merge camp.db bad-edge.db
grep -q "field 'edge' holds 2" err.txt || { cat err.txt >&2; fail "merge: no clear message"; }
[ "$(sqlite3 camp.db 'select count(*) from events')" = "$before" ] || fail "merge of a bad board changed the campaign"
cp good.db orphan.db
sqlite3 orphan.db 'update events set session_id = 99 where seq = 7'
expect_exit 65 "$M2MLAT" stats orphan.db
grep -q "row seq 7: field 'session_id' holds 99 (expected an existing session)" err.txt ||
  { cat err.txt >&2; fail "stats: no clear message for an orphan event"; }

# Not a store at all.
printf 'SQLite format 2 and then some text that is no database at all....\n' > text.db
expect_exit 65 "$M2MLAT" merge camp.db text.db
grep -q "text.db: not an m2mlat store (not an SQLite database)" err.txt || { cat err.txt >&2; fail "text file"; }
mkdir dir.db
expect_exit 65 "$M2MLAT" merge camp.db dir.db
grep -q "dir.db: not an m2mlat store (a directory)" err.txt || { cat err.txt >&2; fail "directory"; }
mkfifo fifo.db
expect_exit 65 timeout 5 "$M2MLAT" merge camp.db fifo.db  # refused by stat(), never opened: no hang
grep -q "fifo.db: not an m2mlat store (not a regular file)" err.txt || { cat err.txt >&2; fail "fifo"; }
[ "$(sqlite3 camp.db 'select count(*) from events')" = "$before" ] || fail "the campaign store changed"
echo "ok: damaged and foreign stores refused with exit 65, the campaign store unchanged"

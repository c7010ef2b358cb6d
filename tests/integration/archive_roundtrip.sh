# The archive round trip against a real PostgreSQL server started here (tests/support/pg_server.bash;
# exit 77 without Debian's postgresql): two campaigns pushed, pushed again (nothing added), a large
# campaign's push killed (SIGKILL) midway and pushed again; every event is in the archive exactly
# once (counts and a checksum of every seq and ns value equal the stores'), `stats` and `report` of
# the archive equal those of the stores, the filters select across campaigns, and bad input is
# refused with the documented exit codes, changing nothing and printing no password.
PG=$(realpath "$(dirname "$0")/../support/pg_server.bash")  # before lib.bash changes the folder
source "$(dirname "$0")/lib.bash"

rc=0
URL=$(bash "$PG" start "$WORK") || rc=$?
[ "$rc" = 77 ] && exit 77
[ "$rc" = 0 ] || fail "the PostgreSQL server did not start"
stop_server() { bash "$PG" stop "$WORK"; cleanup; }
trap stop_server EXIT
sql() { psql "$URL" -XAtq -v ON_ERROR_STOP=1 -c "$1"; }

"$M2MLAT" demo --store a.db >/dev/null
"$M2MLAT" demo --store b.db --seed 7 --scenario static_wifi --scenario static_5g >/dev/null
"$M2MLAT" simulate --store big.db --seed 11 --scenario static_5g --manoeuvres 40000 >/dev/null

# A store's events as the archive must hold them: count and md5 over every (seq, session, ns, seqnos, flags).
store_sum() {
  "$PY" - "$1" <<'PY'
import hashlib, sqlite3, sys
rows = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True).execute(
    "SELECT seq, session_id, t_ns, seqno, line_seqno, flags FROM events ORDER BY seq").fetchall()
print(len(rows), hashlib.md5(",".join(":".join(map(str, r)) for r in rows).encode()).hexdigest())
PY
}
archive_sum() {
  sql "SELECT count(*) || ' ' || md5(COALESCE(string_agg(concat_ws(':', e.seq, e.session_id, e.t_ns, e.seqno,
       e.line_seqno, e.flags), ',' ORDER BY e.seq), '')) FROM m2mlat.events e JOIN m2mlat.campaigns c
       ON c.id = e.campaign_id WHERE c.name = '$1'"
}
check_sums() {
  local name
  for name in "$@"; do
    [ "$(archive_sum "$name")" = "$(store_sum "$name.db")" ] ||
      fail "campaign $name: archive $(archive_sum "$name") != store $(store_sum "$name.db")"
  done
}

# Two campaigns, then both again: the second push adds nothing.
"$M2MLAT" archive push a.db "$URL" --rig rig-a --label study1 >push1.txt
"$M2MLAT" archive push b.db "$URL" --rig rig-b --label study2 >>push1.txt
grep -q "campaign 'a'" push1.txt || fail "no summary: $(cat push1.txt)"
check_sums a b
"$M2MLAT" archive push a.db b.db "$URL" >push2.txt
[ "$(grep -c ': resumed, 0 events, 0 clock samples, 0 losses, 0 sessions added' push2.txt)" = 2 ] ||
  fail "a second push added rows: $(cat push2.txt)"
check_sums a b
[ "$(sql "SELECT string_agg(rig || '/' || label, ' ' ORDER BY name) FROM m2mlat.campaigns")" = "rig-a/study1 rig-b/study2" ] ||
  fail "a push without --rig/--label changed them"

# A large campaign's push killed midway (small batches: many transactions), then run again.
total=$(store_sum big.db | cut -d' ' -f1)
"$M2MLAT" archive push big.db "$URL" --label soak --batch 500 >push3.txt 2>&1 &
pid=$!
PIDS+=("$pid")
for _ in $(seq 1 400); do
  n=$(sql "SELECT COALESCE(sum(events), 0) FROM m2mlat.push_cursors p JOIN m2mlat.campaigns c ON c.id = p.campaign_id
           WHERE c.name = 'big'" 2>/dev/null || echo 0)
  [ "${n:-0}" -gt 0 ] && break
  sleep 0.02
done
kill -KILL "$pid"
wait "$pid" 2>/dev/null || true
held=$(sql "SELECT count(*) FROM m2mlat.events e JOIN m2mlat.campaigns c ON c.id = e.campaign_id WHERE c.name = 'big'")
[ "$held" -gt 0 ] && [ "$held" -lt "$total" ] || fail "the push was not killed midway: $held of $total events"
[ "$(sql "SELECT complete FROM m2mlat.push_cursors p JOIN m2mlat.campaigns c ON c.id = p.campaign_id WHERE c.name = 'big'")" = f ] ||
  fail "a killed push is marked complete"
"$M2MLAT" archive list "$URL" >list1.txt
grep -q "^big .*partial" list1.txt || fail "list does not show the partial push: $(cat list1.txt)"
"$M2MLAT" archive push big.db "$URL" >push4.txt
grep -q "resumed, $((total - held)) events" push4.txt || fail "the resumed push did not add the rest: $(cat push4.txt)"
check_sums a b big
echo "killed after $held of $total events; resumed"

# Every row once: primary keys hold, and the other tables match the stores' counts.
for name in a b big; do
  want=$("$PY" -c "import sqlite3,sys; c=sqlite3.connect('file:$name.db?mode=ro', uri=True); print(*[c.execute(f'SELECT count(*) FROM {t}').fetchone()[0] for t in ('sessions','clock_samples','losses')])")
  got=$(sql "SELECT (SELECT count(*) FROM m2mlat.sessions s WHERE s.campaign_id = c.id) || ' ' ||
             (SELECT count(*) FROM m2mlat.clock_samples k WHERE k.campaign_id = c.id) || ' ' ||
             (SELECT count(*) FROM m2mlat.losses l WHERE l.campaign_id = c.id) FROM m2mlat.campaigns c WHERE c.name = '$name'")
  [ "$got" = "$want" ] || fail "campaign $name: sessions/clock samples/losses $got in the archive, $want in the store"
done

# A gyroscope's raw trace (three blocks of samples): its BLOBs in the archive are the store's, byte for byte.
"$PY" - <<'PY'
with open("trace.csv", "w") as f:
    f.write("# format: m2mlat-gyro/1\n# clock: realtime\n# counts_per_deg_s: 131\ntime_ns,bound_ns,x,y,z\n")
    for i in range(10000):
        f.write(f"{1764086400000000000 + i * 125000},{80000 + i % 50},{(i * 37) % 65536 - 32768},{-(i % 300)},{32767 - i % 3}\n")
PY
"$M2MLAT" import trace.csv --store gyro.db --node vehicle --channel wheel_gyro >/dev/null
"$M2MLAT" archive push gyro.db "$URL" --rig rig-g >push5.txt
want=$("$PY" -c "import hashlib,sqlite3; c=sqlite3.connect('file:gyro.db?mode=ro', uri=True); r=c.execute('SELECT count(*), sum(count), group_concat(counts_per_deg_s) FROM rate_blocks').fetchone(); b=b''.join(x[0] for x in c.execute('SELECT samples FROM rate_blocks ORDER BY id')); print(r[0], r[1], hashlib.md5(b).hexdigest())")
got=$(sql "SELECT count(*) || ' ' || sum(r.count) || ' ' || md5(string_agg(r.samples, ''::bytea ORDER BY r.id))
           FROM m2mlat.rate_blocks r JOIN m2mlat.campaigns c ON c.id = r.campaign_id WHERE c.name = 'gyro'")
[ "$got" = "$want" ] || fail "raw samples: archive $got, store $want"
"$M2MLAT" archive push gyro.db "$URL" | grep -q "resumed, 0 events" || fail "a second push of the trace added rows"
[ "$(sql "SELECT count(*) FROM m2mlat.rate_blocks")" = "$(echo "$want" | cut -d' ' -f1)" ] || fail "rate blocks twice"

# Read back: stats and report of an archived campaign are the store's, number for number.
"$M2MLAT" stats "$URL" --label study1 --json >arch_a.json
"$M2MLAT" stats a.db --json >store_a.json
cmp arch_a.json store_a.json || fail "stats of campaign a from the archive differ from the store's"
"$M2MLAT" stats --archive "$URL" --rig rig-b --json >arch_b.json
"$M2MLAT" stats b.db --json >store_b.json
cmp arch_b.json store_b.json || fail "stats of campaign b from the archive differ from the store's"
"$M2MLAT" stats "$URL" --label soak --json >arch_big.json
"$M2MLAT" stats big.db --json >store_big.json
cmp arch_big.json store_big.json || fail "stats of the resumed campaign differ from the store's"
"$M2MLAT" report "$URL" --label study1 --print json >report_arch.json
"$M2MLAT" report a.db --print json >report_store.json
"$PY" - <<'PY'
import json
a, s = json.load(open("report_arch.json")), json.load(open("report_store.json"))
for d in (a, s):
    d.pop("generated", None); d.pop("created", None)
assert a["scenarios"] == s["scenarios"], "report scenarios differ"
assert a.get("comparisons") == s.get("comparisons"), "report comparisons differ"
PY

# Across campaigns: a scenario several campaigns hold is <campaign>/<scenario>; filters by date.
"$M2MLAT" stats "$URL" --scenario static_5g --json >shared.json
"$PY" - <<'PY'
import json
names = [s["scenario"] for s in json.load(open("shared.json"))["scenarios"]]
assert names == ["a/static_5g", "b/static_5g", "big/static_5g"], names
PY
"$M2MLAT" archive list "$URL" --since 2020-01-01 --until 2099-12-31 --json >all.json
"$PY" -c 'import json; d=json.load(open("all.json")); assert [c["name"] for c in d["campaigns"]] == ["gyro","a","b","big"], d; assert all(c["complete"] for c in d["campaigns"]), d'
"$M2MLAT" archive list "$URL" --since 2099-01-01 >none.txt
grep -q ": 0 campaigns" none.txt || fail "--since did not filter: $(cat none.txt)"
expect_exit 66 "$M2MLAT" stats "$URL" --rig no-such-rig
"$M2MLAT" stats "$URL" --campaign b --json >arch_b2.json
cmp arch_b2.json store_b.json || fail "--campaign b selected other than campaign b"

# The connection string from a file and from the PG* variables, never printed with its password.
echo "$URL" >url.txt
"$M2MLAT" archive list --url-file url.txt | grep -q ": 4 campaigns" || fail "--url-file"
host=${URL#*host=}; host=${host%%&*}
PGHOST=$host PGUSER=m2mlat PGDATABASE=lab "$M2MLAT" archive list | grep -q ": 4 campaigns" || fail "PG* variables"
expect_exit 74 "$M2MLAT" archive list "postgresql://m2mlat:s3cret-pw@/lab?host=$WORK/no-such-dir"
grep -q "cannot connect" err.txt || fail "no connection error: $(cat err.txt)"
! grep -q "s3cret-pw" err.txt out.txt || fail "the password was printed: $(cat err.txt)"
expect_exit 2 "$M2MLAT" archive list "postgresql://[bad"
expect_exit 2 "$M2MLAT" archive list "$URL" --since 2026-13-01
grep -q -- "--since" err.txt || fail "the date error does not name the flag: $(cat err.txt)"

# The fleet dashboard's SQL (docs/grafana/fleet.json) runs on this archive, Grafana's macros and the
# rig variable replaced as Grafana does: every query of the dashboard matches the schema.
"$PY" - "$DATA/../../docs/grafana/fleet.json" >queries.sql <<'PY'
import json, sys
dash = json.load(open(sys.argv[1]))
for p in dash["panels"]:
    for t in p.get("targets", []):
        if "rawSql" in t:
            q = t["rawSql"].replace("$__unixEpochFrom()", "0").replace("$__unixEpochTo()", "4102444800")
            print(q.replace("$rig", "'rig-a','rig-b'") + ";")
PY
[ "$(grep -c ';$' queries.sql)" -ge 4 ] || fail "the dashboard has no SQL panels"
psql "$URL" -XAtq -v ON_ERROR_STOP=1 -f queries.sql >dashboard_rows.txt || fail "a query of docs/grafana/fleet.json failed"
grep -q "^a|rig-a|study1|" dashboard_rows.txt || fail "the dashboard's campaigns table lacks campaign a"

# Bad stores change nothing.
before=$(sql "SELECT count(*) FROM m2mlat.events")
echo "not a store" >junk.db
expect_exit 66 "$M2MLAT" archive push missing.db "$URL"
expect_exit 65 "$M2MLAT" archive push junk.db "$URL"
grep -q "junk.db" err.txt || fail "the error does not name the store: $(cat err.txt)"
[ "$(sql "SELECT count(*) FROM m2mlat.events")" = "$before" ] || fail "a refused push changed the archive"
echo "archive_roundtrip: ok"

# A 1 ns difference survives import -> store -> export, at an epoch time a double cannot hold.
source "$(dirname "$0")/lib.bash"
cat > in.csv <<'CSV'
# format: m2mlat-events/1
node,channel,edge,clock,time_ns,seqno,line_seqno,flags
operator,wheel,falling,realtime,1762872545550296135,1,1,0
vehicle,wheel,falling,realtime,1762872546417585462,1,1,0
operator,wheel,falling,realtime,1762872549550296135,2,2,0
vehicle,wheel,falling,realtime,1762872550417585463,2,2,0
CSV
"$M2MLAT" import --store s.db in.csv > /dev/null
"$M2MLAT" export s.db -o out.csv
grep -q ',1762872550417585463,' out.csv || fail "the 1 ns step was lost: $(cat out.csv)"
grep -q ',1762872546417585462,' out.csv || fail "timestamp changed"
"$M2MLAT" export s.db --what pairs -o pairs.csv
grep -q ',867289327,867.289327' pairs.csv || fail "first latency not exact: $(cat pairs.csv)"
grep -q ',867289328,867.289328' pairs.csv || fail "second latency not exact: $(cat pairs.csv)"
echo "1 passed, 0 failed"

# A throwaway PostgreSQL server for the archive's tests (Debian's postgresql package): initdb and
# pg_ctl in a folder of the test's own, listening only on a unix socket in that folder (no TCP port,
# so tests never collide), fsync off. PostgreSQL refuses to run as root: as root (CI) the server runs
# as the unprivileged user nobody, and the folder is made reachable for it.
#   bash pg_server.bash start DIR   prints the connection string of database "lab" (exit 77: no initdb)
#   bash pg_server.bash stop DIR    stops it (immediate shutdown)
set -euo pipefail
cmd=$1 dir=$2
initdb=$(command -v initdb 2>/dev/null || ls -d /usr/lib/postgresql/*/bin/initdb 2>/dev/null | sort -V | tail -n 1 || true)
bin=$(dirname "$(readlink -f "${initdb:-/nonexistent}")")
if [ ! -x "$bin/initdb" ]; then
  echo "SKIP: initdb not found (Debian's postgresql package is not installed: apt-get install postgresql)" >&2
  exit 77
fi
as_server() {
  if [ "$(id -u)" = 0 ]; then setpriv --reuid=nobody --regid=nogroup --clear-groups -- "$@"; else "$@"; fi
}
case $cmd in
  start)
    mkdir -p "$dir/pg"
    if [ "$(id -u)" = 0 ]; then
      chown nobody:nogroup "$dir/pg"
      chmod o+x "$dir"  # mktemp makes it 0700; the folders above (/tmp) are open already
      as_server test -w "$dir/pg" ||
        { echo "FAIL: the user nobody cannot reach $dir/pg (a folder above it is closed)" >&2; exit 1; }
    fi
    as_server "$bin/initdb" -D "$dir/pg/data" -U m2mlat -A trust -E UTF8 --locale=C --no-sync >"$dir/pg/initdb.log" 2>&1 ||
      { cat "$dir/pg/initdb.log" >&2; exit 1; }
    as_server "$bin/pg_ctl" -D "$dir/pg/data" -l "$dir/pg/server.log" -w -t 30 \
      -o "-c listen_addresses= -k $dir/pg -c fsync=off -c synchronous_commit=off -c full_page_writes=off" start \
      >/dev/null || { cat "$dir/pg/server.log" >&2; exit 1; }
    "$bin/psql" -X -q -h "$dir/pg" -U m2mlat -d postgres -c 'CREATE DATABASE lab' >/dev/null
    echo "postgresql:///lab?host=$dir/pg&user=m2mlat"
    ;;
  stop)
    as_server "$bin/pg_ctl" -D "$dir/pg/data" -m immediate -w stop >/dev/null 2>&1 || true
    ;;
  *) echo "usage: pg_server.bash start|stop DIR" >&2; exit 64 ;;
esac

#!/usr/bin/env bash
# The SEMAP database: a local PostgreSQL cluster (PostGIS + SFCGAL) on a loopback port, no systemd.
#   scripts/semap-db.sh init   DIR PORT [DBNAME]   initdb into DIR/data (once)
#   scripts/semap-db.sh start  DIR PORT [DBNAME]   init if needed, start, create DBNAME + schema
#   scripts/semap-db.sh stop   DIR PORT            fast shutdown
#   scripts/semap-db.sh status DIR PORT            exit 0 when running, 3 when not
#   scripts/semap-db.sh run    DIR PORT [DBNAME]   start, wait for SIGINT/SIGTERM, stop (roslaunch)
# Idempotent. As root the server runs as the postgres user (DIR is chowned to it); otherwise as the
# calling user. DBNAME defaults to semap; the schema is sql/semap_schema.sql + sql/semap_relations.sql.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH

usage() { sed -n '2,9p' "$0" >&2; exit 2; }
[[ $# -ge 3 ]] || usage
cmd=$1 dir=$2 port=$3 db=${4:-semap}
[[ $port =~ ^[0-9]+$ ]] || { echo "semap-db: PORT must be a number, not '$port'" >&2; exit 2; }
sql_dir=$(cd "$(dirname "$0")/../sql" 2>/dev/null && pwd || true)

pg_bin=${PG_BIN:-}
if [[ -z $pg_bin ]]; then
  for d in /usr/lib/postgresql/15/bin $(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -rV); do
    [[ -x $d/pg_ctl ]] && { pg_bin=$d; break; }
  done
fi
[[ -n $pg_bin && -x $pg_bin/pg_ctl ]] || {
  echo "semap-db: PostgreSQL binaries not found (apt-get install postgresql-15 postgresql-15-postgis-3)" >&2; exit 4; }

as_owner() {  # run a command line as the cluster's owner
  if [[ $(id -u) -eq 0 ]]; then (cd / && su postgres -s /bin/sh -c "$1"); else sh -c "$1"; fi
}
data=$dir/data
psql_q() { PGOPTIONS="-c client_min_messages=warning" "$pg_bin/psql" -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p "$port" -U postgres "$@"; }

running() { [[ -f $data/PG_VERSION ]] && as_owner "'$pg_bin/pg_ctl' -D '$data' status" >/dev/null 2>&1; }

init() {
  if [[ -f $data/PG_VERSION ]]; then return 0; fi
  mkdir -p "$dir"
  [[ $(id -u) -eq 0 ]] && chown postgres: "$dir"
  as_owner "'$pg_bin/initdb' -D '$data' -U postgres -A trust -E UTF8 --locale=C.UTF-8" >"$dir/initdb.log" 2>&1 || {
    cat "$dir/initdb.log" >&2; exit 1; }
  echo "semap-db: initialised $data"
}

start() {
  init
  if running; then
    echo "semap-db: already running ($data)"
  else
    as_owner "'$pg_bin/pg_ctl' -D '$data' -l '$dir/postgres.log' -w -t 30 \
      -o \"-p $port -k '$dir' -c listen_addresses=127.0.0.1\" start" >/dev/null || {
      tail -20 "$dir/postgres.log" >&2; exit 1; }
    echo "semap-db: started on 127.0.0.1:$port ($data)"
  fi
  if [[ -z $(psql_q -d postgres -tAc "SELECT 1 FROM pg_database WHERE datname = '$db'") ]]; then
    psql_q -d postgres -c "CREATE DATABASE \"$db\""
  fi
  if [[ -n $sql_dir && -f $sql_dir/semap_schema.sql ]]; then
    # One transaction holding the installer lock that semap_bridge takes too: a bridge reconnecting
    # while this runs would otherwise fail both with "tuple concurrently updated".
    psql_q -d "$db" -1 -c "SELECT pg_advisory_xact_lock(7362770)" \
      -f "$sql_dir/semap_schema.sql" -f "$sql_dir/semap_relations.sql" >/dev/null
  fi
  echo "semap-db: database '$db' ready: psql -h 127.0.0.1 -p $port -U postgres $db"
}

stop() {
  if running; then
    as_owner "'$pg_bin/pg_ctl' -D '$data' -m fast -w stop" >/dev/null
    echo "semap-db: stopped ($data)"
  else
    echo "semap-db: not running ($data)"
  fi
}

case $cmd in
  init) init ;;
  start) start ;;
  stop) stop ;;
  status) if running; then echo "semap-db: running ($data)"; else echo "semap-db: not running ($data)"; exit 3; fi ;;
  run)
    start
    trap 'stop; exit 0' INT TERM
    while running; do sleep 1 & wait $!; done
    echo "semap-db: the server stopped by itself" >&2; exit 1 ;;
  *) usage ;;
esac

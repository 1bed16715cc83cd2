#!/usr/bin/env bash
# The SEMAP database: a local PostgreSQL cluster (PostGIS + SFCGAL) on a loopback port, no systemd.
#   scripts/semap-db.sh init   DIR PORT [DBNAME]   initdb into DIR/data (once)
#   scripts/semap-db.sh start  DIR PORT [DBNAME]   init if needed, start, create DBNAME + schema
#   scripts/semap-db.sh stop   DIR PORT            fast shutdown
#   scripts/semap-db.sh status DIR PORT            exit 0 when running, 3 when not
#   scripts/semap-db.sh run    DIR PORT [DBNAME]   start, wait for SIGINT/SIGTERM, stop (roslaunch)
# Idempotent. As root the server runs as the postgres user (DIR is chowned to it); otherwise as the
# calling user. DBNAME defaults to semap; the schema is sql/semap_schema.sql + sql/semap_relations.sql.
# Access: SCRAM passwords only (no trust), TCP on 127.0.0.1 only, the socket in DIR/socket (0700).
# Two roles: postgres (superuser, password in DIR/superuser.pgpass) and semap_bridge (no superuser,
# owns DBNAME and its tables; password in DIR/bridge.pgpass, what semap_bridge's ~db_passfile reads).
# Both files are libpq password files (0600, the calling user's); the passwords are generated.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH

usage() { sed -n '2,14p' "$0" >&2; exit 2; }
[[ $# -ge 3 ]] || usage
cmd=$1 dir=$2 port=$3 db=${4:-semap}
[[ $port =~ ^[0-9]+$ ]] || { echo "semap-db: PORT must be a number, not '$port'" >&2; exit 2; }
[[ $db =~ ^[a-z_][a-z0-9_]*$ ]] || { echo "semap-db: DBNAME must be [a-z_][a-z0-9_]*, not '$db'" >&2; exit 2; }
sql_dir=$(cd "$(dirname "$0")/../sql" 2>/dev/null && pwd || true)
bridge_role=semap_bridge

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
socket=$dir/socket
superuser_pass=$dir/superuser.pgpass
bridge_pass=$dir/bridge.pgpass
psql_q() {
  PGPASSFILE=$superuser_pass PGOPTIONS="-c client_min_messages=warning" \
    "$pg_bin/psql" -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p "$port" -U postgres "$@"
}

running() { [[ -f $data/PG_VERSION ]] && as_owner "'$pg_bin/pg_ctl' -D '$data' status" >/dev/null 2>&1; }

new_password() { head -c 24 /dev/urandom | base64 | tr -d '/+=\n'; }
password_of() { cut -d: -f5- "$1"; }
# A libpq password file for ROLE on this port, 0600, created once.
write_passfile() {
  local file=$1 role=$2
  [[ -s $file ]] && return 0
  (umask 077; echo "127.0.0.1:$port:*:$role:$(new_password)" >"$file")
}

init() {
  if [[ -f $data/PG_VERSION ]]; then return 0; fi
  mkdir -p "$dir"
  write_passfile "$superuser_pass" postgres
  write_passfile "$bridge_pass" "$bridge_role"
  local pwfile
  pwfile=$(mktemp)
  password_of "$superuser_pass" >"$pwfile"
  if [[ $(id -u) -eq 0 ]]; then chown postgres: "$dir" "$pwfile"; fi
  as_owner "'$pg_bin/initdb' -D '$data' -U postgres -A scram-sha-256 --pwfile='$pwfile' -E UTF8 --locale=C.UTF-8" \
    >"$dir/initdb.log" 2>&1 || { rm -f "$pwfile"; cat "$dir/initdb.log" >&2; exit 1; }
  rm -f "$pwfile"
  echo "semap-db: initialised $data (SCRAM passwords in $superuser_pass and $bridge_pass)"
}

# A cluster made before passwords were required (trust lines in pg_hba.conf): give the superuser
# its password, then require it everywhere. Runs while the server is up.
harden() {
  grep -Eq '^[^#]*[[:space:]]trust([[:space:]]|$)' "$data/pg_hba.conf" 2>/dev/null || return 0
  write_passfile "$superuser_pass" postgres
  write_passfile "$bridge_pass" "$bridge_role"
  PGOPTIONS="-c client_min_messages=warning" "$pg_bin/psql" -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p "$port" \
    -U postgres -d postgres -v pw="$(password_of "$superuser_pass")" <<<"ALTER ROLE postgres PASSWORD :'pw'"
  as_owner "sed -i -E 's/^([^#]*[[:space:]])trust([[:space:]]|\$)/\1scram-sha-256\2/' '$data/pg_hba.conf'"
  as_owner "'$pg_bin/pg_ctl' -D '$data' reload" >/dev/null
  echo "semap-db: $data allowed connections without a password: now SCRAM only"
}

# The bridge's role (login, no superuser), the database it owns, the extensions (superuser, once)
# and the schema, created as the bridge's role so that it owns its tables and functions.
setup_database() {
  psql_q -d postgres -v role="$bridge_role" -v pw="$(password_of "$bridge_pass")" <<'SQL'
SELECT format('CREATE ROLE %I LOGIN NOSUPERUSER NOCREATEDB NOCREATEROLE', :'role')
  WHERE NOT EXISTS (SELECT 1 FROM pg_roles WHERE rolname = :'role') \gexec
ALTER ROLE :"role" PASSWORD :'pw';
SQL
  if [[ -z $(psql_q -d postgres -tAc "SELECT 1 FROM pg_database WHERE datname = '$db'") ]]; then
    psql_q -d postgres -c "CREATE DATABASE \"$db\" OWNER $bridge_role"
  fi
  psql_q -d "$db" -c "ALTER DATABASE \"$db\" OWNER TO $bridge_role" \
    -c "CREATE EXTENSION IF NOT EXISTS postgis" -c "CREATE EXTENSION IF NOT EXISTS postgis_sfcgal"
  # Tables and functions a superuser made (a cluster from before the bridge's role) go to the role.
  psql_q -d "$db" -v role="$bridge_role" <<'SQL'
SELECT format('ALTER TABLE public.%I OWNER TO %I', c.relname, :'role') FROM pg_class c
  WHERE c.relnamespace = 'public'::regnamespace AND c.relkind = 'r'
    AND c.relname IN ('object_class', 'instance', 'pose_history', 'relation_history')
    AND pg_get_userbyid(c.relowner) <> :'role' \gexec
SELECT format('ALTER FUNCTION %s OWNER TO %I', p.oid::regprocedure, :'role') FROM pg_proc p
  WHERE p.pronamespace = 'public'::regnamespace AND p.proname LIKE 'semap\_%'
    AND pg_get_userbyid(p.proowner) <> :'role' \gexec
SQL
  if [[ -n $sql_dir && -f $sql_dir/semap_schema.sql ]]; then
    # One transaction holding the installer lock that semap_bridge takes too: a bridge reconnecting
    # while this runs would otherwise fail both with "tuple concurrently updated".
    psql_q -d "$db" -1 -c "SET ROLE $bridge_role" -c "SELECT pg_advisory_xact_lock(7362770)" \
      -f "$sql_dir/semap_schema.sql" -f "$sql_dir/semap_relations.sql" >/dev/null
  fi
}

start() {
  init
  if running; then
    echo "semap-db: already running ($data)"
  else
    mkdir -p "$socket"
    chmod 0700 "$socket"
    if [[ $(id -u) -eq 0 ]]; then chown postgres: "$socket"; fi
    as_owner "'$pg_bin/pg_ctl' -D '$data' -l '$dir/postgres.log' -w -t 30 \
      -o \"-p $port -k '$socket' -c unix_socket_permissions=0700 -c listen_addresses=127.0.0.1\" start" >/dev/null || {
      tail -20 "$dir/postgres.log" >&2; exit 1; }
    echo "semap-db: started on 127.0.0.1:$port ($data)"
  fi
  harden
  setup_database
  echo "semap-db: database '$db' ready: PGPASSFILE=$bridge_pass psql -h 127.0.0.1 -p $port -U $bridge_role $db"
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

# Sourced by the check scripts (scripts/check-*.sh, part of `make test`): the package root in
# $root, the --xml=RESULT.xml argument in $xml, an empty report file in $report (what goes into it
# is the failure), and `finish CASE`, which writes the JUnit test case style.CASE when asked and
# exits 1 when the report is not empty.
set -uo pipefail
export PATH=/usr/bin:/bin:$PATH
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
xml=""
for a in "$@"; do
  case "$a" in
    --xml=*) xml="${a#--xml=}" ;;
    *) echo "usage: $0 [--xml=RESULT.xml]" >&2; exit 2 ;;
  esac
done
report="$(mktemp)"
trap 'rm -f "$report"' EXIT

finish() {
  [ -n "$xml" ] && /usr/bin/python3 "$root/scripts/junit_case.py" "$xml" style "$1" "$report"
  [ ! -s "$report" ]
}

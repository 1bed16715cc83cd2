#!/usr/bin/env bash
# Function-length check (part of `make test`): no function in the pipeline or the track life cycle
# (src/core/pipeline, src/core/tracking) longer than 60 lines, so each stage and each rule reads
# on one screen. scripts/function_lengths.py measures; run it on any files to see the longest.
#   scripts/check-function-lengths.sh [--xml=RESULT.xml]   (also writes a JUnit test case)
set -uo pipefail
export PATH=/usr/bin:/bin:$PATH
root="$(cd "$(dirname "$0")/.." && pwd)"
xml=""
for a in "$@"; do
  case "$a" in
    --xml=*) xml="${a#--xml=}" ;;
    *) echo "usage: $0 [--xml=RESULT.xml]" >&2; exit 2 ;;
  esac
done
cd "$root"
report="$(mktemp)"
trap 'rm -f "$report"' EXIT
mapfile -t files < <(find src/core/pipeline src/core/tracking -name '*.cpp' | sort)
/usr/bin/python3 scripts/function_lengths.py --top 3 --max 60 --under src/core/pipeline \
  --under src/core/tracking "${files[@]}" 2> "$report"
[ -s "$report" ] && cat "$report"
[ -n "$xml" ] && /usr/bin/python3 "$root/scripts/junit_case.py" "$xml" style function_lengths "$report"
[ ! -s "$report" ]

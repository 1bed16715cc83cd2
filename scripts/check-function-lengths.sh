#!/usr/bin/env bash
# Function-length check (part of `make test`): no function in the pipeline or the track life cycle
# (src/core/pipeline, src/core/tracking) longer than 60 lines, so each stage and each rule reads
# on one screen. scripts/function_lengths.py measures; run it on any files to see the longest.
#   scripts/check-function-lengths.sh [--xml=RESULT.xml]   (also writes a JUnit test case)
source "$(dirname "$0")/check_common.sh" "$@"
cd "$root"
mapfile -t files < <(find src/core/pipeline src/core/tracking -name '*.cpp' | sort)
/usr/bin/python3 scripts/function_lengths.py --top 3 --max 60 --under src/core/pipeline \
  --under src/core/tracking "${files[@]}" 2> "$report"
[ -s "$report" ] && cat "$report"
finish function_lengths

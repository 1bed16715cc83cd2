#!/usr/bin/env bash
# Runs every Google Benchmark program and writes JSON into BUILD/bench/<name>.json.
set -euo pipefail
build="${1:-build}"
out="$build/bench"
mkdir -p "$out"
reps="${BENCH_REPETITIONS:-5}"
for prog in "$build"/benchmark/bench_*; do
  [ -x "$prog" ] || continue
  name="$(basename "$prog")"; name="${name#bench_}"
  echo "== $name -> $out/$name.json"
  "$prog" --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
    --benchmark_out="$out/$name.json" --benchmark_out_format=json ${BENCH_FILTER:+--benchmark_filter="$BENCH_FILTER"}
done

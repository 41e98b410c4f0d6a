#!/bin/sh
# Control tick on the host: callgrind instructions per tick (inclusive of everything Tick calls),
# with the telemetry batching and framing part shown apart. Prints figures; asserts nothing.
set -eu
cd "$(dirname "$0")/../.."
BENCH=build/default/tests/bench/palpa_tick_bench
TICKS=5000
out=$(mktemp)
trap 'rm -f "$out"' EXIT

echo "== firmware/core: instructions per control tick (host x86-64 -O2, callgrind) =="
for config in thesis-5finger full-8; do
  valgrind --tool=callgrind --callgrind-out-file="$out" "$BENCH" "$config" "$TICKS" >/dev/null 2>&1
  callgrind_annotate --inclusive=yes "$out" 2>/dev/null > "$out.txt"
  tick=$(grep -E 'palpa::core::Board::Tick\(' "$out.txt" | head -1 | awk '{gsub(",","",$1); print $1}')
  telemetry=$(grep -E 'palpa::core::TelemetryBatch::Sample\(' "$out.txt" | head -1 | awk '{gsub(",","",$1); print $1}')
  echo "  $config: $(( tick / TICKS )) per tick, of which telemetry batching + framing $(( telemetry / TICKS )) (mean over $TICKS ticks)"
  rm -f "$out.txt"
done

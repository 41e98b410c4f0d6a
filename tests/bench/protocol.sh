#!/bin/sh
# Protocol benchmark: codec throughput, instructions per 8-line telemetry frame (callgrind),
# and a long fuzzing run. Prints figures; asserts nothing about time.
set -eu
cd "$(dirname "$0")/../.."
BENCH=build/default/tests/bench/palpa_protocol_bench
FUZZ=build/fuzz/tests/protocol/protocol_fuzz

echo "== protocol: codec throughput =="
"$BENCH" throughput

echo "== protocol: instructions per encoded telemetry frame (8 lines x 2 ticks, callgrind) =="
count() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$BENCH" frames "$1" 2>&1 |
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
a=$(count 1000)
b=$(count 3000)
echo "  $(( (b - a) / 2000 )) instructions per frame (header+body encode, CRC-32, COBS; x86-64 -O2)"

echo "== protocol: fuzzing (libFuzzer, 2 000 000 executions) =="
corpus=build/fuzz/tests/protocol/fuzz_corpus
mkdir -p "$corpus"
/usr/bin/python3 tests/protocol/fuzz_seeds.py tests/protocol/golden_frames.json "$corpus"
. tests/bench/fuzz_run.inc
fuzz_run protocol "$FUZZ" 2000000 "$corpus" -max_len=1024

#!/bin/sh
# The board fuzzer's long run: scripts of link traffic, configuration edits, updates and hardware
# events against the whole board (tests/firmware/core/fuzz_board.cc). Prints executions, coverage
# and findings; the CTest run of ./run test is the short one.
set -eu
cd "$(dirname "$0")/../.."
FUZZ=build/fuzz/tests/firmware/core/board_fuzz
[ -x "$FUZZ" ] || { echo "board_fuzz.sh: $FUZZ is missing (build the fuzz preset)" >&2; exit 1; }

echo "== board: fuzzing the whole board (libFuzzer, 100 000 scripts) =="
corpus=build/fuzz/board_fuzz_bench_corpus
mkdir -p "$corpus"
/usr/bin/python3 tests/firmware/core/board_fuzz_seeds.py "$corpus"
. tests/bench/fuzz_run.inc
fuzz_run board "$FUZZ" 100000 "$corpus" -max_len=1024

#!/bin/sh
# The board fuzzer's long run: scripts of link traffic, configuration edits and hardware events
# against the whole board (tests/firmware/core/fuzz_board.cc). Prints executions, coverage and
# findings; the CTest run of ./run test is the short one.
set -eu
cd "$(dirname "$0")/../.."
FUZZ=build/fuzz/tests/firmware/core/board_fuzz
[ -x "$FUZZ" ] || { echo "board_fuzz.sh: $FUZZ is missing (build the fuzz preset)" >&2; exit 1; }

echo "== board: fuzzing the whole board (libFuzzer, 300 000 scripts) =="
corpus=build/fuzz/board_fuzz_bench_corpus
findings=build/fuzz/board_findings
mkdir -p "$corpus" "$findings"
/usr/bin/python3 tests/firmware/core/board_fuzz_seeds.py "$corpus"
if "$FUZZ" -runs=300000 -seed=2 -max_len=1024 -artifact_prefix="$findings/" "$corpus" \
    > build/fuzz/board_fuzz_bench.log 2>&1; then
  status=0
else
  status=1
fi
grep -E '^Done' build/fuzz/board_fuzz_bench.log | sed 's/^/  /'
grep -E 'DONE|cov:' build/fuzz/board_fuzz_bench.log | tail -1 | sed 's/^/  /'
echo "  findings: $(ls "$findings" | wc -l) (artifacts in $findings)"
exit $status

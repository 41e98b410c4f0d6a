#!/bin/sh
# palpa-linux-board's tick statistics under load: thesis-5finger on the EK9000 emulator (with its
# stand-in plant) over loopback, a host holding line 1 at 40 kPa and streaming every telemetry
# frame for SECONDS, once with SCHED_FIFO and locked memory asked for and once without. Prints the
# board's own statistics line (the core's, as `palpa diag` reports them). Usage: linux_board.sh
# [SECONDS] (default 20).
set -eu
cd "$(dirname "$0")/../.."
SECONDS_RUN=${1:-20}
BIN=build/default
DIR=$(mktemp -d)
trap 'kill $EMU 2>/dev/null; rm -rf "$DIR"' EXIT
# The emulator picks a free port and announces it (tests/hal/linux/ek9000_emulator.py).
/usr/bin/python3 tests/hal/linux/ek9000_emulator.py 0 1,1,1,1,1,9,9,1 \
  plant=20:1/0.7736,1/0.7736,1/0.7736,1/0.7736,1/0.7736,9/-0.7736,9/-0.7736,1/0 >"$DIR/emulator.log" 2>&1 &
EMU=$!
for _ in $(seq 100); do
  PORT=$(sed -n 's/^listening on tcp:127.0.0.1://p' "$DIR/emulator.log")
  [ -n "$PORT" ] && break
  sleep 0.1
done
[ -n "$PORT" ] || { cat "$DIR/emulator.log" >&2; echo "linux_board.sh: the emulator did not start" >&2; exit 1; }
for PRIORITY in 50 0; do
  cat >"$DIR/board.json" <<JSON
{"board": "thesis-5finger", "link": {"listen": "tcp:127.0.0.1:0"}, "realtime": {"priority": $PRIORITY},
 "analog_module": {"port": $PORT, "watchdog_ms": 300, "outputs": {"count": 8},
                   "inputs": {"count": 8, "bits": 14}}}
JSON
  $BIN/firmware/boards/linux/palpa-linux-board "$DIR/board.json" >"$DIR/board.log" 2>&1 &
  BOARD=$!
  sleep 1
  ADDRESS=$(sed -n 's/.*listening on //p' "$DIR/board.log")
  $BIN/host/cli/palpa --device "$ADDRESS" monitor --duration "$SECONDS_RUN" >/dev/null 2>&1 &
  MONITOR=$!
  $BIN/host/cli/palpa --device "$ADDRESS" line 1=40 --hold "$SECONDS_RUN" >/dev/null 2>&1 || true
  wait $MONITOR || true
  kill -TERM $BOARD
  wait $BOARD || true
  echo "realtime.priority $PRIORITY: $(sed -n 's/^palpa-linux-board: real time: //p' "$DIR/board.log")"
  grep ' ticks, ' "$DIR/board.log"
done

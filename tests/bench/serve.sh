#!/bin/sh
# palpa serve under load: 20 watchers and a chromium page on a board sending 8 lines at 1 kHz.
# PALPA_SERVE_SECONDS sets the run's length (default 10).
set -eu
cd "$(dirname "$0")/../.."
B=build/default
/usr/bin/python3 tests/bench/serve_bench.py $B/host/cli/palpa $B/firmware/boards/sim/palpa-sim \
  "${PALPA_SERVE_SECONDS:-10}"

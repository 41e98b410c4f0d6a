#!/bin/sh
# Fast steps: settling, overshoot and steady-state error of pneumatic and jamming vacuum steps on
# held-out simulated units, each way of driving the line; writes its figures and charts into docs/.
# Then where a deep jamming step spends its time (printed; docs/performance.md, "Deep vacuum steps").
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_steps_bench docs
build/default/tests/bench/palpa_deep_step_bench

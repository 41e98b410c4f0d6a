#!/bin/sh
# Fast steps: settling, overshoot and steady-state error of pneumatic and jamming vacuum steps on
# held-out simulated units, each way of driving the line; writes its figures and charts into docs/.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_steps_bench docs

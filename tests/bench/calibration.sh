#!/bin/sh
# Calibration: held-out stiffness-map error against indentation cycles and rig time for the
# thesis grid and the adaptive protocol (several seeds, each a held-out simulated unit), and the
# failure detectors' detection and false-positive rates. Writes docs/calibration.svg,
# docs/calibration_time.svg and the calibration-bench block of docs/calibration.md.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_calibration_bench docs

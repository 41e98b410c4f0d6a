#!/bin/sh
# Plant and pressure loop: step responses with the regulators' static errors on, and the plant's
# charts against the thesis. Writes the charts into docs/.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_step_bench docs/step_response.svg
build/default/tests/bench/palpa_plant_charts docs

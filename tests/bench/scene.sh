#!/bin/sh
# Scenes: speed against accuracy — straight and hand-like passes across the three-cube phantom with
# the example scene on the simulated board (virtual time), the fingers on their nominal curves and
# each calibrated by palpa calibrate's protocol (steps shaped): error against the rule's target at
# each finger's current position, and the edge lag at cube B, per speed and per finger. Then input sample → DAC write latency through the scene on
# palpa-sim in real time, on one clock. Figures recorded in docs/scenes.md.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_scene_bench docs/examples/scene_three_cube.json
build/default/tests/bench/palpa_scene_latency_bench docs/examples/scene_three_cube.json 3000

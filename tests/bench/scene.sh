#!/bin/sh
# Scenes: speed against accuracy — straight and hand-like passes across the three-cube phantom with
# the example scene on the simulated board (virtual time), along the cubes' mid-line and a second
# line that brings the triangle's third finger over them; the fingers on their nominal curves and
# each calibrated by palpa calibrate's protocol (steps shaped): error against the rule's target at
# each finger's current position, each finger's speed at cube B's face and its edge lag there, per
# speed and per finger. Then prediction off and on: the mid-line's passes on the calibrated fingers,
# each input rendered as it is and ahead of the fingers' calibrated delay — error, edge lag at B and
# at every cube face any finger crosses either way, and how much prediction changes each edge's
# lag. Then input sample → DAC write latency through the scene on palpa-sim in real time, on one
# clock (the fingers calibrated: steps shaped, the chamber estimated from the outlet). Figures
# recorded in docs/scenes.md.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_scene_bench docs/examples/scene_three_cube.json
build/default/tests/bench/palpa_scene_predict_bench docs/examples/scene_three_cube.json
build/default/tests/bench/palpa_scene_latency_bench docs/examples/scene_three_cube.json 3000

#!/bin/sh
# Scenes: speed against accuracy — straight passes across the three-cube phantom with the example
# scene on the simulated board (virtual time): error against the rule's target at each finger's
# current position, and the edge lag at cube B, per speed. Figures recorded in docs/scenes.md.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_scene_bench docs/examples/scene_three_cube.json

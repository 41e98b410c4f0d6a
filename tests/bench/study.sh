#!/bin/sh
# Studies: where the controller's accuracy meets the person's — a two-finger detection study with
# the tumour finger 5–30 % deeper, run by the study runner on palpa-sim and answered by the
# simulated participant, on nominal fingers and on fingers calibrated without and with
# compensation: the display's error and the participant's accuracy. Figures and chart recorded in
# docs/studies.md and docs/study_accuracy.svg.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_study_accuracy_bench

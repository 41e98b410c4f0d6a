#!/bin/sh
# Link figures: command -> output latency (pty, TCP), telemetry at full rate (pty, TCP), the link
# under injected faults at full size, and host loss at full size. PALPA_TELEMETRY_SECONDS=600 for
# the 10-minute telemetry run.
set -eu
cd "$(dirname "$0")/../.."
B=build/default/tests/bench
SECONDS_TELEMETRY=${PALPA_TELEMETRY_SECONDS:-60}
$B/palpa_latency_bench pty 10000
$B/palpa_latency_bench tcp 10000
$B/palpa_telemetry_bench pty "$SECONDS_TELEMETRY"
$B/palpa_telemetry_bench tcp "$SECONDS_TELEMETRY"
$B/palpa_link_faults_bench
$B/palpa_host_loss_bench 1000

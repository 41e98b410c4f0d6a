#!/bin/sh
# Firmware update: a thousand power cuts at random points of an update, each followed by a boot
# (the tally of what booted), and the time a 64 KiB image takes over a simulated 1 Mbaud link
# against the link's raw capacity. Writes the update-bench block of docs/flashing.md.
set -eu
cd "$(dirname "$0")/../.."
build/default/tests/bench/palpa_update_bench docs

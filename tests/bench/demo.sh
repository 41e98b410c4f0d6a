#!/bin/sh
# The demo's trace plot for docs/ (the same run ./run demo shows).
set -eu
cd "$(dirname "$0")/../.."
build/default/host/cli/palpa demo --out docs/demo.svg | tail -6

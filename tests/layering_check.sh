#!/bin/sh
# The command line is the host library's client: what it does, an application can do through the
# library, so no host/cli file reaches past it into the firmware core (palpa/core/).
set -eu
cd "$(dirname "$0")/.."
if grep -n '#include *"palpa/core/' host/cli/*.cc host/cli/*.h; then
  echo "layering_check: host/cli includes palpa/core/ (move that flow into the host library)"
  exit 1
fi
echo "layering_check: host/cli includes nothing of palpa/core/"

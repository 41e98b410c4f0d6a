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
# The server stands where the command line does: above the host library, never into the core, and
# nothing below it knows it.
if grep -rn '#include *"palpa/core/' host/serve; then
  echo "layering_check: host/serve includes palpa/core/ (go through the host library)"
  exit 1
fi
if grep -rn '#include *"palpa/serve/' host/lib calibration firmware protocol hal; then
  echo "layering_check: a layer below host/serve includes it"
  exit 1
fi
echo "layering_check: host/serve stands on the host library alone"

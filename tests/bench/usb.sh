#!/bin/sh
# USB figures through a real kernel (the real-kernel guest's usb scenario in bench mode, see
# docs/kernel_tests.md): command -> dispatch latency over vendor bulk, HID and CDC-ACM with a pty
# and TCP in the same guest (PALPA_USB_COMMANDS each); telemetry of 8 lines at 1 kHz over vendor
# bulk for 60 s (PALPA_USB_TELEMETRY_SECONDS), over CDC-ACM, and over HID at every tick and
# decimated. The guest runs on virtual time (-icount, PALPA_USB_ICOUNT=SHIFT, default 1: 2 ns an
# instruction), so its figures follow its own work and not the load on this machine; they are for
# comparison between transports and between runs, not a PC's. About 11 minutes.
set -eu
cd "$(dirname "$0")/../.."
B=build/default
exec /usr/bin/python3 tests/kernel/guest.py --kernel build/kernel/current \
  --scenario tests/kernel/usb --work $B/tests/kernel/usb-bench --timeout 1200 --icount "${PALPA_USB_ICOUNT:-1}" \
  --bin $B/firmware/boards/sim/palpa-sim --bin $B/firmware/boards/gadget/palpa-gadget \
  --bin $B/tests/bench/palpa_latency_bench --bin $B/tests/bench/palpa_telemetry_bench \
  -- bench "${PALPA_USB_TELEMETRY_SECONDS:-60}" "${PALPA_USB_COMMANDS:-1000}"

#!/bin/sh
# The USB scenario, in the guest: palpa-sim behind palpa-gadget on the device side of dummy_hcd;
# the host side runs the suite (test) or the benchmarks (bench).
#   guest.sh test | bench
set -u
mode=${1:-test}

fail() { echo "usb scenario: $*"; exit 1; }

# start_board CONFIG [SIM OPTIONS...]: palpa-sim on a loopback port, the gadget bridged to it,
# waiting until the host side has enumerated all three interfaces.
start_board() {
  config=$1
  shift
  palpa-sim --config "$config" --listen tcp:127.0.0.1:5555 "$@" > /tmp/sim.log 2>&1 &
  sim_pid=$!
  for _ in $(seq 50); do grep -q "listening on" /tmp/sim.log && break; sleep 0.1; done
  palpa-gadget --sim tcp:127.0.0.1:5555 > /tmp/gadget.log 2>&1 &
  gadget_pid=$!
  for _ in $(seq 150); do
    [ -e /dev/hidraw0 ] && [ -e /dev/ttyACM0 ] && grep -q "bridged" /tmp/gadget.log && break
    sleep 0.2
  done
  cat /tmp/gadget.log
  [ -e /dev/hidraw0 ] && [ -e /dev/ttyACM0 ] || { dmesg | tail -20; fail "the gadget did not enumerate"; }
  export PALPA_GADGET_CONFIGFS=$(sed -n 's/^palpa-gadget: configfs //p' /tmp/gadget.log)
  export PALPA_GADGET_UDC=$(sed -n 's/.* on \([^ ]*\) (.*/\1/p' /tmp/gadget.log)
  export PALPA_GADGET_TTY=/dev/ttyACM0
  echo "usb scenario: $(cat /sys/bus/usb/devices/1-1/product), $(cat /sys/bus/usb/devices/1-1/speed) Mbit/s"
}

stop_board() {
  kill "$gadget_pid" "$sim_pid" 2>/dev/null
  wait "$gadget_pid" "$sim_pid" 2>/dev/null
}

case "$mode" in
  test)
    start_board thesis-5finger
    palpa list | tee /tmp/list.txt
    grep -q "^  usb:1209:0001:0001 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget on vendor bulk"
    grep -q "^  hid:1209:0001:0001 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget on HID"
    grep -q "^  serial:/dev/ttyACM0 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget's serial port"
    palpa_guest_usb_tests -v
    status=$?
    stop_board
    exit $status
    ;;
  *)
    fail "unknown mode '$mode' (test or bench)"
    ;;
esac

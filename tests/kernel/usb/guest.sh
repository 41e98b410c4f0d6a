#!/bin/sh
# The USB scenario, in the guest: palpa-sim behind palpa-gadget on the device side of dummy_hcd;
# the host side runs the suite (test) or the benchmarks (bench).
#   guest.sh test | bench [TELEMETRY_SECONDS] [COMMANDS]
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

# What the host side sees of the gadget (sysfs, from the descriptors the kernel read): full speed,
# as an MCU's USB; a vendor interface with 64-byte bulk IN and OUT; a HID interface with 64-byte
# interrupt IN and OUT polled every 1 ms; CDC-ACM (its control and data interfaces).
check_descriptors() {
  dev=/sys/bus/usb/devices/1-1
  [ "$(cat $dev/speed)" = 12 ] || fail "the gadget runs at $(cat $dev/speed) Mbit/s, not 12 (full speed)"
  for intf in "$dev"/1-1:1.*; do
    for ep in "$intf"/ep_*; do
      echo "$(cat "$intf/bInterfaceClass") $(cat "$ep/type") $(cat "$ep/direction")" \
        "$(cat "$ep/wMaxPacketSize") $(cat "$ep/interval")"
    done
  done > /tmp/endpoints.txt
  cat /tmp/endpoints.txt
  for expected in "ff Bulk in 0040" "ff Bulk out 0040" "03 Interrupt in 0040 1ms" \
    "03 Interrupt out 0040 1ms" "02 Interrupt in" "0a Bulk in 0040" "0a Bulk out 0040"; do
    grep -q "^$expected" /tmp/endpoints.txt || fail "no endpoint '$expected' (class, type, direction, packet, interval)"
  done
}

stop_board() {
  kill "$gadget_pid" "$sim_pid" 2>/dev/null
  wait "$gadget_pid" "$sim_pid" 2>/dev/null
}

case "$mode" in
  test)
    start_board thesis-5finger
    check_descriptors
    palpa list | tee /tmp/list.txt
    grep -q "^  usb:1209:0001:0001 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget on vendor bulk"
    grep -q "^  hid:1209:0001:0001 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget on HID"
    grep -q "^  serial:/dev/ttyACM0 .*palpa board: palpa actuator board" /tmp/list.txt ||
      fail "palpa list did not find the gadget's serial port"
    # The CLI says what happens to its link: the cable pulled and plugged back in under monitor.
    palpa --device usb:1209:0001 --json monitor --duration 8 > /dev/null 2> /tmp/monitor.txt &
    monitor=$!
    sleep 2
    echo "" > "$PALPA_GADGET_CONFIGFS/UDC"
    sleep 1
    echo "$PALPA_GADGET_UDC" > "$PALPA_GADGET_CONFIGFS/UDC"
    wait "$monitor" || fail "palpa monitor failed: $(cat /tmp/monitor.txt)"
    cat /tmp/monitor.txt
    grep -q "was lost" /tmp/monitor.txt && grep -q "reopened usb:1209:0001" /tmp/monitor.txt ||
      fail "palpa monitor did not report the unplug and the replug"
    palpa_guest_usb_tests -v
    status=$?
    stop_board
    exit $status
    ;;
  bench)
    seconds=${2:-60}
    commands=${3:-1000}
    # Command -> dispatch latency: the same board and benchmark over each interface, then over a
    # pty and TCP with palpa-sim alone (PALPA_SIM: the benchmark starts it).
    # palpa-sim writes its stamps whole when it stops: a fresh board for each interface.
    for uri in usb:1209:0001 hid:1209:0001 serial:/dev/ttyACM0; do
      rm -f /tmp/stamps.txt
      start_board thesis-pneumatic-3 --stamp file:/tmp/stamps.txt
      palpa_latency_bench --device "$uri" --stamps /tmp/stamps.txt --stop "$sim_pid" "$commands" ||
        exit 1
      stop_board
      for _ in $(seq 50); do [ -e /dev/ttyACM0 ] || [ -e /dev/hidraw0 ] || break; sleep 0.1; done
    done
    PALPA_SIM=/bin/palpa-sim palpa_latency_bench pty "$commands" || exit 1
    PALPA_SIM=/bin/palpa-sim palpa_latency_bench tcp "$commands" || exit 1
    # Telemetry, 8 lines at 1 kHz: vendor bulk at every tick; HID at every tick and decimated.
    start_board full-8
    palpa_telemetry_bench --device usb:1209:0001 "$seconds" 1
    palpa_telemetry_bench --device serial:/dev/ttyACM0 10 1
    for every in 1 2 3 4; do palpa_telemetry_bench --device hid:1209:0001 10 "$every"; done
    kill -USR1 "$gadget_pid"
    sleep 1
    tail -n 1 /tmp/gadget.log
    stop_board
    ;;
  *)
    fail "unknown mode '$mode' (test or bench)"
    ;;
esac

#!/bin/sh
# The GPIO and watchdog scenario, in the guest: hal/linux's GPIO classes on gpio-mockup's lines,
# WatchdogDevice on the i6300esb, the study's trigger line (palpa study run and palpa serve), then a
# watchdog reset. A phase marker on the virtual disk (/dev/vda, kept across the reset) tells the
# second boot what the first did.
set -u

fail() { echo "gpio scenario: $*"; exit 1; }
mark() { printf '%-16s\n' "$1" | dd of=/dev/vda conv=fsync 2>/dev/null || fail "cannot write /dev/vda"; }

[ -b /dev/vda ] || fail "no virtual disk /dev/vda"
phase=$(head -c 16 /dev/vda | tr -d ' \0\n')
case "$phase" in
  "")
    ;;
  unclean-close)
    # Second boot: the i6300esb reset the machine after the controller died without the magic
    # close; its driver reports that as the boot status.
    palpa_guest_gpio_tests after-reset
    exit $?
    ;;
  *)
    fail "the machine reset during phase '$phase' (a kick or the magic close did not hold it)"
    ;;
esac

mount -t debugfs none /sys/kernel/debug || fail "cannot mount debugfs"
chip=$(ls /sys/kernel/debug/gpio-mockup/)
[ "$(echo "$chip" | wc -w)" -eq 1 ] || fail "expected one gpio-mockup chip, found '$chip'"
[ -c "/dev/$chip" ] || fail "no /dev/$chip"
export PALPA_GPIO_CHIP="$chip"
echo "gpio scenario: $chip, $(ls "/sys/kernel/debug/gpio-mockup/$chip" | wc -l) lines; $(cat /sys/class/watchdog/watchdog0/identity)"

mark tests
palpa_guest_gpio_tests -v || exit 1

# The study's trigger line: palpa study run pulses gpio-mockup's line 6 at every trigger event; the
# kernel's gpio_value trace events show each level the line was set to.
out=$(palpa study run /scenario/study.json --participant G1 --out /tmp/G1 --trigger-gpio "$chip:99" \
  --simulated-participant 1 2>&1) && fail "a missing trigger line was not refused"
echo "$out" | grep -q "no line 99" || fail "a missing trigger line was refused without naming it: $out"
[ -d /tmp/G1 ] && fail "a refused run left /tmp/G1 behind"
mount -t tracefs none /sys/kernel/tracing || fail "cannot mount tracefs"
base=$(sed -n 's/^gpiochip.*: GPIOs \([0-9]*\)-.*gpio-mockup.*/\1/p' /sys/kernel/debug/gpio)
# levels LINE: each level the kernel's trace shows the mockup's line LINE set to, with its time.
levels() {
  sed -n "s/.* \([0-9.]*\): gpio_value: $((base + $1)) set \([01]\)$/\1 \2/p" /sys/kernel/tracing/trace
}
# pulsed N: a line taken low by palpa, then pulsed once for each of N events.
pulsed() { echo 0; for _ in $(seq "$1"); do printf '1\n0\n'; done; }
echo 1 > /sys/kernel/tracing/events/gpio/gpio_value/enable
palpa study run /scenario/study.json --participant G1 --out /tmp/G1 --speed 20 \
  --simulated-participant 1 --triggers /tmp/triggers.jsonl --trigger-gpio "$chip:6" ||
  fail "palpa study run with a trigger line failed"
events=$(wc -l < /tmp/triggers.jsonl)
echo "gpio scenario: $events trigger events, line levels (time, level): $(levels 6 | tr '\n' ' ')"
[ "$events" -eq 4 ] || fail "the study wrote $events trigger events, not 4 (two trials)"
[ "$(levels 6 | cut -d' ' -f2)" = "$(pulsed "$events")" ] ||
  fail "the trigger line did not pulse once per event ($events events)"

# The same study through palpa serve (its board palpa-sim at 20x): the session started and answered
# over the API, the server's trigger line (line 7) pulsed at each of the two trials' four events.
palpa-sim --config thesis-pneumatic-3 --listen tcp:127.0.0.1:7100 --speed 20 > /tmp/sim.log 2>&1 &
sim=$!
for _ in $(seq 100); do grep -q "listening on" /tmp/sim.log && break; sleep 0.05; done
palpa serve --device tcp:127.0.0.1:7100 --listen 127.0.0.1:7180 --study-dir /tmp/S \
  --study /scenario/study.json --trigger-gpio "$chip:7" > /tmp/serve.log 2>&1 &
serve=$!
palpa_guest_study_client serve:127.0.0.1:7180 trigger-line S1 > /tmp/client.log ||
  fail "the study through palpa serve did not complete: $(cat /tmp/client.log /tmp/serve.log)"
cat /tmp/client.log
grep -q "trigger line is $chip:7" /tmp/client.log || fail "study.list did not name the trigger line"
kill "$serve"
wait "$serve" || fail "palpa serve did not stop cleanly: $(cat /tmp/serve.log)"
kill "$sim"
echo 0 > /sys/kernel/tracing/events/gpio/gpio_value/enable
trials=$(wc -l < /tmp/S/trigger-line/S1/trials.jsonl)
echo "gpio scenario: palpa serve, $trials trials, line levels (time, level): $(levels 7 | tr '\n' ' ')"
[ "$trials" -eq 2 ] || fail "the session through palpa serve kept $trials trials, not 2"
[ "$(levels 7 | cut -d' ' -f2)" = "$(pulsed 4)" ] ||
  fail "palpa serve's trigger line did not pulse once per event (4 events)"

# The controller dies without the magic close: the watchdog stays armed and must reset the machine
# (1 s timeout: QEMU's i6300esb runs each of its two stages for half of it); 10 s without one fails.
mark unclean-close
palpa_guest_gpio_tests unclean-close || exit 1
echo "gpio scenario: left armed at uptime $(cut -d' ' -f1 /proc/uptime) s"
# The uptime every 0.25 s until the reset: the last one printed bounds when it came.
for _ in $(seq 40); do
  sleep 0.25
  echo "gpio scenario: up $(cut -d' ' -f1 /proc/uptime) s"
done
fail "no reset 10 s after the watchdog was left armed"

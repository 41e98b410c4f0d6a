#!/bin/sh
# The Linux board scenario, in the guest: palpa-linux-board as the USB gadget on dummy_hcd's
# device side, its valves and E-stop on gpio-mockup lines, its watchdog on the i6300esb, its
# analogue I/O module the EK9000 emulator on the machine running QEMU (10.0.2.2, user network).
#   guest.sh test MODULE_PORT
set -u
fail() { echo "linux board scenario: $*"; exit 1; }
[ "${1:-}" = test ] && [ -n "${2:-}" ] || fail "usage: guest.sh test MODULE_PORT"

ip link set eth0 up || fail "no network interface (virtio_net)"
ip addr add 10.0.2.15/24 dev eth0
ip route add default via 10.0.2.2
mount -t debugfs none /sys/kernel/debug || fail "cannot mount debugfs"
chip=$(ls /sys/kernel/debug/gpio-mockup/)
[ "$(echo "$chip" | wc -w)" -eq 1 ] || fail "expected one gpio-mockup chip, found '$chip'"
[ -c /dev/watchdog ] || fail "no /dev/watchdog (i6300esb)"
echo "linux board scenario: $chip; $(cat /sys/class/watchdog/watchdog0/identity); module at 10.0.2.2:$2"
PALPA_GPIO_CHIP=$chip PALPA_MODULE=10.0.2.2:$2 palpa_guest_linux_board_tests -v

#!/bin/sh
# The guest's /init: says it booted, mounts, loads the scenario's modules in dependency order with
# their options, runs its script with the arguments given on the kernel command line, reports its
# exit status and powers off.
export PATH=/bin LD_LIBRARY_PATH=/lib:/usr/lib
echo "palpa-guest: boot"
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mkdir -p /dev/pts /dev/shm
mount -t devpts devpts /dev/pts
mount -t tmpfs tmpfs /tmp
mount -t tmpfs tmpfs /run
ln -sf /proc/self/fd /dev/fd
ip link set lo up 2>/dev/null
version=$(uname -r)
status=0
while read -r module options; do
  # shellcheck disable=SC2086
  if ! insmod "/lib/modules/$version/$module" $options 2>/tmp/insmod.err; then
    echo "palpa-guest: cannot load $module: $(cat /tmp/insmod.err)"
    status=3
  fi
done < /scenario/modules
grep -qw configfs /proc/filesystems && mount -t configfs none /sys/kernel/config
args=$(sed -n 's/.*palpa\.args=\([^ ]*\).*/\1/p' /proc/cmdline | tr ',' ' ')
if [ "$status" -eq 0 ]; then
  # shellcheck disable=SC2086
  sh /scenario/guest.sh $args
  status=$?
fi
sync
echo "palpa-guest: exit $status"
poweroff -f

#!/usr/bin/python3
"""Boots Debian's kernel under QEMU (TCG) with a small initramfs and runs one scenario in it.

The initramfs holds busybox, the kernel modules the scenario names (with what they depend on), the
given programs (without their debug information) with their shared libraries, the common /init and the scenario's guest script.
The guest's console goes to stdout; the exit status is the scenario script's.

  guest.py --kernel DIR --scenario DIR [--bin PROGRAM]... [--module FILE.ko]... [--timeout S]
           [--work DIR] [--icount SHIFT] [-- ARGS]

DIR for --kernel is where `./run` unpacked the kernel package (boot/vmlinuz-*, lib/modules/*).
--module adds a module built out of tree for this kernel, loaded after the scenario's.
A scenario directory holds scenario.json, guest.sh (run by /init with ARGS; its exit status is
the guest's) and any files guest.sh reads (in /scenario). scenario.json: {"modules": [...],
"module_options": {"module": "param=value ..."}, "memory_mb": N, "cpus": N, "qemu": [extra
arguments], "disk_kb": N, "reboots": N, "icount_sleep": true|false}. disk_kb gives the guest a zeroed virtio disk (/dev/vda)
that keeps what it writes across a reset; reboots lets the machine reset that many times (a
watchdog's reset) before the scenario ends, where otherwise a reset ends QEMU and fails the run.
--icount SHIFT runs the guest on virtual time, 2^SHIFT ns an instruction, idle time skipped: its
clocks then follow its own work, not the load on the machine running it (benchmarks); with
"icount_sleep" its idle time passes in real time (for a peer on this machine).
"""

import argparse
import json
import os
import re
import select
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

MARKER = "palpa-guest: exit "


def fail(message):
    print("guest.py: " + message, file=sys.stderr)
    sys.exit(2)


class Cpio:
    """A newc archive written as files are added (the format the kernel unpacks)."""

    def __init__(self, out):
        self.out = out
        self.ino = 1
        self.dirs = set()

    def _entry(self, name, mode, data=b""):
        header = "070701" + "".join(
            "%08X" % v
            for v in (self.ino, mode, 0, 0, 1, 0, len(data), 0, 0, 0, 0, len(name) + 1, 0))
        self.ino += 1
        self.out.write(header.encode() + name.encode() + b"\0")
        self.out.write(b"\0" * ((4 - (110 + len(name) + 1) % 4) % 4))
        self.out.write(data)
        self.out.write(b"\0" * ((4 - len(data) % 4) % 4))

    def directory(self, path):
        path = path.strip("/")
        if not path or path in self.dirs:
            return
        self.directory(os.path.dirname(path))
        self.dirs.add(path)
        self._entry(path, stat.S_IFDIR | 0o755)

    def file(self, path, data, mode=0o644):
        path = path.strip("/")
        self.directory(os.path.dirname(path))
        self._entry(path, stat.S_IFREG | mode, data)

    def symlink(self, path, target):
        path = path.strip("/")
        self.directory(os.path.dirname(path))
        self._entry(path, stat.S_IFLNK | 0o777, target.encode())

    def close(self):
        self._entry("TRAILER!!!", 0)


def find_kernel(kernel_dir):
    boot = os.path.join(kernel_dir, "boot")
    images = sorted(f for f in os.listdir(boot) if f.startswith("vmlinuz-")) if os.path.isdir(
        boot) else []
    if len(images) != 1:
        fail("%s: expected one boot/vmlinuz-* (found %d); fetch the kernel with ./run kernel" %
             (kernel_dir, len(images)))
    version = images[0][len("vmlinuz-"):]
    modules = os.path.join(kernel_dir, "lib", "modules", version)
    if not os.path.isdir(modules):
        fail("%s: no modules for %s" % (kernel_dir, version))
    return os.path.join(boot, images[0]), version, modules


def module_index(modules_dir):
    index = {}
    for root, _, files in os.walk(os.path.join(modules_dir, "kernel")):
        for f in files:
            if f.endswith(".ko"):
                index[f[:-3].replace("-", "_")] = os.path.join(root, f)
    return index


def module_depends(path):
    with open(path, "rb") as f:
        data = f.read()
    found = re.search(rb"\0depends=([^\0]*)\0", data)
    if not found or not found.group(1):
        return []
    return found.group(1).decode().split(",")


def module_load_order(names, index):
    """The modules and everything they depend on, each after its dependencies."""
    order, seen = [], set()

    def visit(name, chain):
        key = name.replace("-", "_")
        if key in seen:
            return
        if key not in index:
            fail("kernel module '%s' (needed by %s) is not in the kernel package" %
                 (name, " <- ".join(chain) or "the scenario"))
        seen.add(key)
        for dep in module_depends(index[key]):
            visit(dep, [name] + chain)
        order.append(index[key])

    for name in names:
        visit(name, [])
    return order


def shared_libraries(programs):
    libs = set()
    for program in programs:
        out = subprocess.run(["ldd", program], capture_output=True, text=True)
        if out.returncode != 0 and "not a dynamic executable" in out.stdout + out.stderr:
            continue
        for line in out.stdout.splitlines():
            m = re.search(r"(\S*/\S+) \(0x", line)
            if "not found" in line:
                fail("%s: %s" % (program, line.strip()))
            if m:
                libs.add(m.group(1))
    return sorted(libs)


def without_debug_info(program):
    """The program's bytes without its debug information: nothing is debugged in the guest, and a
    RelWithDebInfo build's (130 MB for palpa, 4 MB of code) would not unpack in its memory."""
    strip = shutil.which("strip")
    if strip is None:
        fail("strip is not installed (binutils, which g++ brings)")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, os.path.basename(program))
        subprocess.run([strip, "--strip-debug", "-o", out, program], check=True)
        with open(out, "rb") as f:
            return f.read()


def build_initramfs(path, scenario_dir, config, modules_dir, version, programs, extra_modules):
    busybox = shutil.which("busybox")
    if busybox is None:
        fail("busybox is not installed (./run installs busybox-static)")
    here = os.path.dirname(os.path.abspath(__file__))
    with open(path, "wb") as out:
        a = Cpio(out)
        for d in ("dev", "proc", "sys", "tmp", "run", "etc"):
            a.directory(d)
        with open(busybox, "rb") as f:
            a.file("bin/busybox", f.read(), 0o755)
        applets = subprocess.run([busybox, "--list"], capture_output=True, text=True).stdout
        for applet in applets.split():
            if applet != "busybox":
                a.symlink("bin/" + applet, "busybox")
        a.symlink("sbin", "bin")
        a.symlink("usr/bin", "../bin")
        a.symlink("usr/sbin", "../bin")
        with open(os.path.join(here, "init.sh"), "rb") as f:
            a.file("init", f.read(), 0o755)
        for name in sorted(os.listdir(scenario_dir)):  # guest.sh and the files it reads
            path = os.path.join(scenario_dir, name)
            if name != "scenario.json" and os.path.isfile(path):
                with open(path, "rb") as f:
                    a.file("scenario/" + name, f.read(), 0o755 if name == "guest.sh" else 0o644)
        # Modules built out of tree (against the same kernel's headers) join the package's: they
        # are loaded after what they depend on, like the others.
        index = module_index(modules_dir)
        for ko in extra_modules:
            index[os.path.basename(ko)[:-3].replace("-", "_")] = os.path.abspath(ko)
        names = config.get("modules", []) + [os.path.basename(k)[:-3] for k in extra_modules]
        order = module_load_order(names, index)
        for ko in order:
            with open(ko, "rb") as f:
                a.file("lib/modules/%s/%s" % (version, os.path.basename(ko)), f.read())
        options = config.get("module_options", {})
        lines = []
        for ko in order:
            name = os.path.basename(ko)
            option = options.get(name[:-3].replace("-", "_"))
            lines.append(name + (" " + option if option else "") + "\n")
        a.file("scenario/modules", "".join(lines).encode())
        for program in programs:
            a.file("bin/" + os.path.basename(program), without_debug_info(program), 0o755)
        for lib in shared_libraries(programs):
            with open(lib, "rb") as f:  # stored under the name programs ask for
                a.file(lib, f.read(), 0o755)
        a.close()


def run_guest(kernel, initrd, config, append, timeout, work, icount):
    qemu = shutil.which("qemu-system-x86_64")
    if qemu is None:
        fail("qemu-system-x86_64 is not installed (./run installs qemu-system-x86)")
    # On virtual time QEMU 7.2 runs every CPU in one thread, and this kernel did not boot with two.
    cpus = 1 if icount is not None else config.get("cpus", 2)
    reboots = config.get("reboots", 0)
    command = [
        qemu, "-accel", "tcg", "-m", str(config.get("memory_mb", 512)), "-smp",
        str(cpus), "-nographic", "-monitor", "none", "-serial", "stdio", "-nodefaults",
        "-kernel", kernel, "-initrd", initrd, "-append",
        "console=ttyS0 panic=-1 loglevel=4 " + append
    ] + ([] if reboots else ["-no-reboot"]) + config.get("qemu", [])
    if "disk_kb" in config:
        disk = os.path.join(work, "disk.img")
        with open(disk, "wb") as f:
            f.write(b"\0" * 1024 * config["disk_kb"])
        command += ["-drive", "file=%s,format=raw,if=virtio" % disk]
    if icount is not None:
        # sleep=off skips idle time; a scenario with a peer outside the guest (a Modbus module on
        # this machine) keeps idle time to real time, so the guest waits for it as a board would.
        sleep = "on" if config.get("icount_sleep", False) else "off"
        command += ["-icount", "shift=%d,sleep=%s" % (icount, sleep)]
    started = time.monotonic()
    child = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, start_new_session=True)
    status = None
    pending = b""
    boots = 0
    partial = b""
    with open(os.path.join(work, "console.log"), "wb") as log:
        while True:
            left = started + timeout - time.monotonic()
            if left <= 0:
                print("\nguest.py: the guest did not finish within %d s" % timeout, flush=True)
                break
            ready, _, _ = select.select([child.stdout], [], [], min(left, 1.0))
            if not ready:
                continue
            chunk = os.read(child.stdout.fileno(), 65536)
            if not chunk:
                break
            log.write(chunk)
            sys.stdout.buffer.write(chunk)
            sys.stdout.flush()
            # Whole lines are counted: each boot's /init says so first.
            *lines, partial = (partial + chunk).split(b"\n")
            boots += sum(1 for line in lines if line.strip() == b"palpa-guest: boot")
            pending = (pending + chunk)[-4096:]
            if boots > reboots + 1:
                print("\nguest.py: the guest booted %d times, %d allowed" % (boots, reboots + 1),
                      flush=True)
                break
            m = re.search(rb"palpa-guest: exit (\d+)\r?\n", pending)
            if m:
                status = int(m.group(1))
                break
    try:
        child.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.wait()
    print("guest.py: guest ran %.1f s" % (time.monotonic() - started), flush=True)
    return 1 if status is None else status


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--kernel", required=True)
    p.add_argument("--scenario", required=True)
    p.add_argument("--bin", action="append", default=[])
    p.add_argument("--timeout", type=int, default=240)
    p.add_argument("--work", default=None)
    p.add_argument("--icount", type=int, default=None)
    p.add_argument("--module", action="append", default=[])
    p.add_argument("args", nargs="*")
    o = p.parse_args()
    kernel, version, modules_dir = find_kernel(o.kernel)
    with open(os.path.join(o.scenario, "scenario.json")) as f:
        config = json.load(f)
    for program in o.bin:
        if not os.access(program, os.X_OK):
            fail("%s: not an executable (build it first)" % program)
    for ko in o.module:
        if not ko.endswith(".ko") or not os.path.isfile(ko):
            fail("%s: not a kernel module file (.ko; ./run kernel builds gpio-mockup.ko)" % ko)
    work = o.work or os.path.join(os.getcwd(), "guest-" + os.path.basename(o.scenario.rstrip("/")))
    os.makedirs(work, exist_ok=True)
    initrd = os.path.join(work, "initramfs.cpio")
    build_initramfs(initrd, o.scenario, config, modules_dir, version, o.bin, o.module)
    append = "palpa.args=" + ",".join(o.args) if o.args else ""
    sys.exit(run_guest(kernel, initrd, config, append, o.timeout, work, o.icount))


if __name__ == "__main__":
    main()

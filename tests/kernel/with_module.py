#!/usr/bin/python3
"""Runs guest.py with the EK9000 emulator (tests/hal/linux/ek9000_emulator.py) and a stand-in
plant serving on this machine, where the guest reaches it over QEMU's user network (10.0.2.2).

  with_module.py VOLTS PLANT -- GUEST.PY ARGS...

Every "{port}" in the arguments becomes the emulator's port: the free one it picked on 127.0.0.1
and announced ("listening on tcp:127.0.0.1:PORT"), as it does for the C++ tests
(tests/hal/linux/ek9000_process.h).
"""
import os
import select
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
if len(sys.argv) < 5 or sys.argv[3] != "--":
    print(__doc__, file=sys.stderr)
    sys.exit(2)
emulator = subprocess.Popen([
    sys.executable,
    os.path.join(here, "..", "hal", "linux", "ek9000_emulator.py"), "0", sys.argv[1], sys.argv[2]
], stdout=subprocess.PIPE, text=True)
try:
    port = None
    deadline = time.monotonic() + 10  # Python and pymodbus start in well under a second
    while port is None and time.monotonic() < deadline:
        if select.select([emulator.stdout], [], [], 0.1)[0]:
            line = emulator.stdout.readline()
            if not line:
                sys.exit("with_module.py: the emulator exited (%s)" % emulator.wait())
            if line.startswith("listening on tcp:"):
                port = int(line.rsplit(":", 1)[1])
    if port is None:
        sys.exit("with_module.py: the emulator did not announce its port within 10 s")
    args = [a.replace("{port}", str(port)) for a in sys.argv[4:]]
    status = subprocess.call([sys.executable] + args)
finally:
    emulator.kill()
    emulator.wait()
sys.exit(status)

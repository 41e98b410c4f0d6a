#!/usr/bin/python3
"""Runs guest.py with the EK9000 emulator (tests/hal/linux/ek9000_emulator.py) and a stand-in
plant serving on this machine, where the guest reaches it over QEMU's user network (10.0.2.2).

  with_module.py VOLTS PLANT -- GUEST.PY ARGS...

Every "{port}" in the arguments becomes the emulator's port (a free one on 127.0.0.1).
"""
import os
import socket
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
if len(sys.argv) < 5 or sys.argv[3] != "--":
    print(__doc__, file=sys.stderr)
    sys.exit(2)
with socket.socket() as s:
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
emulator = subprocess.Popen([
    sys.executable,
    os.path.join(here, "..", "hal", "linux", "ek9000_emulator.py"),
    str(port), sys.argv[1], sys.argv[2]
])
try:
    for _ in range(100):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            if emulator.poll() is not None:
                sys.exit("with_module.py: the emulator exited (%d)" % emulator.returncode)
            time.sleep(0.1)
    else:
        sys.exit("with_module.py: the emulator did not listen on %d within 10 s" % port)
    args = [a.replace("{port}", str(port)) for a in sys.argv[4:]]
    status = subprocess.call([sys.executable] + args)
finally:
    emulator.kill()
    emulator.wait()
sys.exit(status)

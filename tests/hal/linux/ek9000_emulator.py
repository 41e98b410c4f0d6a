#!/usr/bin/python3
"""A Beckhoff EK9000 Modbus TCP coupler with 0-10 V output and input terminals, for the tests.

Serves the coupler's registers as docs/linux.md gives them (output image at 0x0800, input image at
0x0000 as status and value words, watchdog at 0x1120-0x1123) and implements its watchdog: after the
first write to the output image, a silence longer than the watchdog time sets every output to zero
(fallback 0) or leaves it (fallback 1, freeze); type 0 counts only writes to the output image as
life, type 1 any telegram, type 2 turns the watchdog off. 0x1021 counts the fallbacks.
Usage: ek9000_emulator.py PORT|rtu:DEVICE VOLTS[,VOLTS...] [plant=TAU_MS:A/G[,A/G...]]
  (TCP on 127.0.0.1:PORT, or RTU at 115200 8N1 on DEVICE; the input terminals' voltages, nan: a
  wire break)
  PORT 0: a free port the system picks. Over TCP, once the server accepts connections, it prints
  "listening on tcp:127.0.0.1:PORT" (the line palpa-sim announces itself with): callers wait for
  that line and read the port from it, with no free port to guess and no race for it.
  plant=...: a stand-in for the plant behind the module, so a closed loop can be seen: input i
  follows A + G x (output i's volts), clamped to 0-10 V, through a first-order lag of TAU_MS
  (a regulator and its pressure sensor, linear; not the project's plant model).
"""
import asyncio
import math
import sys
import threading
import time

from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.server import StartSerialServer
from pymodbus.server.async_io import ModbusTcpServer
from pymodbus.transaction import ModbusRtuFramer

OUTPUTS, OUTPUT_WORDS = 0x0800, 16
FALLBACKS, WD_TIME, WD_RESET, WD_TYPE, FALLBACK = 0x1021, 0x1120, 0x1121, 0x1122, 0x1123
FULL_SCALE = 0x7FFF

where = sys.argv[1]
volts = [float(v) for v in sys.argv[2].split(",")]
lock = threading.RLock()
state = {"armed": False, "last": 0.0}


def alive():
    state["last"] = time.monotonic()


class Holding(ModbusSequentialDataBlock):
    def setValues(self, address, values):
        with lock:
            super().setValues(address, values)
            if OUTPUTS <= address < OUTPUTS + OUTPUT_WORDS:
                state["armed"] = True
                alive()
            elif self.word(WD_TYPE) == 1:
                alive()

    def getValues(self, address, count=1):
        with lock:
            if self.word(WD_TYPE) == 1:
                alive()
            return super().getValues(address, count)

    def word(self, address):
        return self.values[address - self.address]


class Inputs(ModbusSequentialDataBlock):
    def getValues(self, address, count=1):
        with lock:
            if holding.word(WD_TYPE) == 1:
                alive()
        return super().getValues(address, count)


image = []
for v in volts:
    if v != v:  # nan: a broken wire, as the EL3064 reports it (overrange and error, full scale)
        image += [0x0042, FULL_SCALE]
    else:
        image += [0, max(0, min(FULL_SCALE, round(v / 10.0 * FULL_SCALE)))]  # status, value
holding = Holding(0, [0] * 0x1200)
holding.values[WD_TIME], holding.values[WD_TYPE], holding.values[FALLBACK] = 1000, 1, 0


def watchdog():
    while True:
        time.sleep(0.005)
        with lock:
            limit = holding.word(WD_TIME) / 1000.0
            if not state["armed"] or holding.word(WD_TYPE) == 2:
                continue
            if time.monotonic() - state["last"] > limit:
                state["armed"] = False  # the next write to the output image starts it again
                holding.values[FALLBACKS] += 1
                if holding.word(FALLBACK) == 0:
                    for i in range(OUTPUT_WORDS):
                        holding.values[OUTPUTS + i] = 0


def plant(tau_s, lines):
    last = time.monotonic()
    while True:
        time.sleep(0.001)
        now = time.monotonic()
        keep = math.exp(-(now - last) / tau_s)
        last = now
        with lock:
            for i, (a, g) in enumerate(lines):
                out = holding.values[OUTPUTS + i] * 10.0 / FULL_SCALE
                target = max(0.0, min(10.0, a + g * out))
                volts[i] = target + (volts[i] - target) * keep
                inputs.values[2 * i + 1] = round(volts[i] / 10.0 * FULL_SCALE)


threading.Thread(target=watchdog, daemon=True).start()
inputs = Inputs(0, image + [0] * 16)
if len(sys.argv) > 3 and sys.argv[3].startswith("plant="):
    tau_ms, _, spec = sys.argv[3][6:].partition(":")
    lines = [tuple(float(x) for x in item.split("/")) for item in spec.split(",")]
    threading.Thread(target=plant, args=(float(tau_ms) / 1000.0, lines), daemon=True).start()
context = ModbusServerContext(
    slaves=ModbusSlaveContext(ir=inputs, hr=holding, zero_mode=True), single=True)
if where.startswith("rtu:"):
    StartSerialServer(context=context, framer=ModbusRtuFramer, port=where[4:], baudrate=115200)
else:

    async def serve_tcp(port):
        server = ModbusTcpServer(context, address=("127.0.0.1", port))
        serving = asyncio.create_task(server.serve_forever())
        await server.serving  # bound and listening
        print("listening on tcp:127.0.0.1:%d" % server.server.sockets[0].getsockname()[1],
              flush=True)
        await serving

    asyncio.run(serve_tcp(int(where)))

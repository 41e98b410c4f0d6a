#!/usr/bin/python3
"""An independent Modbus TCP server (pymodbus) for the driver interoperability test.

Serves preset values in unusual byte and word orders and logs every register write, so the test
can check that palpa's driver decodes and encodes them as the register map says.
Usage: pymodbus_rig.py PORT LOGFILE
"""
import struct
import sys

from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.server import StartTcpServer

port, log_path = int(sys.argv[1]), sys.argv[2]
log = open(log_path, "w", buffering=1)


class LoggingBlock(ModbusSequentialDataBlock):
    def setValues(self, address, values):
        super().setValues(address, values)
        log.write(f"write {address} {' '.join(str(v) for v in values)}\n")


def words_be(fmt, value):
    return list(struct.unpack(">HH", struct.pack(">" + fmt, value)))


def swap_bytes(words):
    return [((w & 0xFF) << 8) | (w >> 8) for w in words]


inputs = [0] * 300
# position 12.345 mm as int32 µm, low word first (word_order little)
inputs[100:102] = list(reversed(words_be("i", 12345)))
inputs[102] = 1  # moving
# force 1.5 N as float32, high word first, bytes within each word swapped (byte_order little)
inputs[200:202] = swap_bytes(words_be("f", 1.5))

context = ModbusServerContext(
    slaves=ModbusSlaveContext(ir=ModbusSequentialDataBlock(0, inputs), hr=LoggingBlock(0, [0] * 300), zero_mode=True),
    single=True)
StartTcpServer(context=context, address=("127.0.0.1", port))

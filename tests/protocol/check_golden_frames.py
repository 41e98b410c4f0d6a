#!/usr/bin/python3
"""Independent check of the golden frames: its own COBS decoder, zlib's CRC-32, and the type ids
and body sizes of the message table in docs/protocol.md. Shares no code with the C++ codec."""
import json
import re
import sys
import zlib

MAX_PACKET = 256
RESERVED_FLAGS = 0xF0


def cobs_decode(data):
    """Standard COBS decode of one frame without its delimiter; raises on malformed input."""
    out = bytearray()
    i = 0
    while i < len(data):
        code = data[i]
        if code == 0:
            raise ValueError("zero byte inside frame")
        if i + code > len(data):
            raise ValueError("block runs past the end")
        out += data[i + 1:i + code]
        i += code
        if code < 0xFF and i < len(data):
            out.append(0)
    return bytes(out)


def message_table(doc_path):
    """Rows '| 0x21 | SetLineSetpoints | host | stream | 5–45 | ...' of the generated catalog."""
    table = {}
    row = re.compile(r"^\|\s*0x([0-9A-Fa-f]{2})\s*\|\s*`?(\w+)`?\s*\|[^|]*\|[^|]*\|\s*(\d+)(?:[–-](\d+))?\s*\|")
    with open(doc_path, encoding="utf-8") as doc:
        for line in doc:
            m = row.match(line)
            if m:
                low = int(m.group(3))
                high = int(m.group(4)) if m.group(4) else low
                table[m.group(2)] = (int(m.group(1), 16), low, high)
    if not table:
        raise SystemExit(f"{doc_path}: no message table found")
    return table


def main():
    golden_path, doc_path = sys.argv[1], sys.argv[2]
    table = message_table(doc_path)
    frames = json.load(open(golden_path, encoding="utf-8"))
    failures = 0
    for frame in frames:
        name = frame["name"]
        try:
            wire = bytes.fromhex(frame["hex"])
            if wire[-1] != 0 or 0 in wire[:-1]:
                raise ValueError("must end in the only 0x00")
            raw = cobs_decode(wire[:-1])
            packet, crc = raw[:-4], int.from_bytes(raw[-4:], "little")
            if zlib.crc32(packet) != crc:
                raise ValueError(f"CRC {crc:#010x} != zlib {zlib.crc32(packet):#010x}")
            if not 4 <= len(packet) <= MAX_PACKET:
                raise ValueError(f"packet of {len(packet)} bytes")
            version, type_id, seq, flags = packet[:4]
            if version != 1:
                raise ValueError(f"version {version}")
            if flags & RESERVED_FLAGS:
                raise ValueError(f"reserved flags {flags:#04x}")
            if (seq, flags) != (frame["seq"], frame["flags"]):
                raise ValueError("header seq/flags differ from the record")
            if frame["type"] not in table:
                raise ValueError(f"type {frame['type']} missing from docs/protocol.md")
            doc_id, low, high = table[frame["type"]]
            if type_id != doc_id:
                raise ValueError(f"type id {type_id:#04x}, docs say {doc_id:#04x}")
            if not low <= len(packet) - 4 <= high:
                raise ValueError(f"body {len(packet) - 4} bytes outside docs' {low}-{high}")
        except (ValueError, KeyError, IndexError) as error:
            print(f"FAIL {name}: {error}")
            failures += 1
    print(f"{len(frames) - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

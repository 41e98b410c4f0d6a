#!/usr/bin/python3
"""Writes libFuzzer seed inputs from the golden frames: each as a stream and as a bare packet."""
import json
import os
import shutil
import sys


def cobs_decode(data):
    out = bytearray()
    i = 0
    while i < len(data):
        code = data[i]
        out += data[i + 1:i + code]
        i += code
        if code < 0xFF and i < len(data):
            out.append(0)
    return bytes(out)


def main():
    golden, corpus = sys.argv[1], sys.argv[2]
    # Emptied first: every run starts from these seeds alone, in a clean tree or a used one, so
    # its figures and findings do not depend on what earlier runs added to the corpus.
    shutil.rmtree(corpus, ignore_errors=True)
    os.makedirs(corpus)
    for frame in json.load(open(golden)):
        wire = bytes.fromhex(frame["hex"])
        packet = cobs_decode(wire[:-1])[:-4]
        with open(os.path.join(corpus, frame["name"] + ".stream"), "wb") as f:
            f.write(b"\x00" + wire + wire)
        with open(os.path.join(corpus, frame["name"] + ".packet"), "wb") as f:
            f.write(b"\x01" + packet)
    return 0


if __name__ == "__main__":
    sys.exit(main())

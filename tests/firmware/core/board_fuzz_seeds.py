#!/usr/bin/python3
"""Writes seed scripts for board_fuzz: sessions that configure compensators and run targets.

The opcodes and their arguments are those of board_script.cc's Operate; libFuzzer mutates these
into the scripts it explores, which reach the compensators far sooner than from empty inputs.
"""
import os
import shutil
import sys

THESIS_5FINGER, FULL_8 = 2, 3  # index in the compiled-in configurations


def connect(seq=0):
    return [0, seq]


def ticks(ms, plant=0x81):  # plant 0x81: follows the regulator model, heartbeats on
    out = []
    while ms > 0:
        out += [1, plant, min(ms, 100) - 1]
        ms -= 100
    return out


def target(finger, value):
    return [5, finger, 0, value & 0xFF, value >> 8]


def clear():
    return [9, 1]


def update_op(kind, slot=1, flag=0):
    """Opcode 8 and its first byte: kind % 6 (0 enter, 1 erase, 2 write, 3 activate, 4 confirm,
    5 whole image), the slot in bit 4, a flag in bit 7."""
    what = next(b for b in range(256) if b % 6 == kind and (b >> 4) & 1 == slot and b >> 7 == flag)
    return [8, what]


def update(chunks):
    """Enter, erase and write slot 1 (the inactive one), then activate what was written."""
    out = update_op(0) + [0x00, 0x01]  # enter: 256 * 64 bytes
    out += update_op(1) + [0, 0, 64, 0]  # erase 16 KiB from 0
    for k in range(chunks):
        out += update_op(2) + [199] + [(k * 7 + i) & 0xFF for i in range(200)]
    return out + update_op(3)


def whole_image(body_size, rollback_counter):
    """A well-formed image for slot 1 (enter, erase, writes), then activate it."""
    out = update_op(5) + [0, body_size, 2, 0, rollback_counter]  # flags 0, version 2.0
    out += [(i * 13) & 0xFF for i in range(body_size)]
    return out + update_op(3)


def end_session(what, foreign=False, other=0):
    """Opcode 10: 0 Close, 1 Release, 2 a second host's Hello, 3 Close twice; bit 4 names another
    session (its nonce the session's + 1 + other)."""
    return [10, what | (0x10 if foreign else 0)] + ([other] if foreign else []) + ([other, 0] if what == 2 else [])


def play(finger, api, operators):
    """A PI or API compensator: small offset, w0 ≈ 0.01, thresholds every 4 kPa, weights ≈ 1e-3."""
    out = [7, finger, 2 if api else 1, operators - 1]
    out += [4, 0]  # offset: 1e-2
    out += [4, 64]  # w0: 2e-2
    out += [10] * operators  # thresholds: climbing by 4 kPa
    out += [3, 32] * operators  # weights: 1.5e-3
    if api:
        out += [1, 50, 2, 3, 4]  # two dead zones
    return out


def branch(finger, points):
    out = [7, finger, 0, points - 1, 5, 0, 5]  # band 100, dead band 100 Pa
    out += [25] * points + [10] * points + [9] * points
    return out


def session(config, *steps):
    out = [config] + connect()
    for step in steps:
        out += step
    return bytes(out)


def main():
    corpus = sys.argv[1]
    # Emptied first: every run starts from these seeds alone, in a clean tree or a used one, so
    # its figures and findings do not depend on what earlier runs added to the corpus.
    shutil.rmtree(corpus, ignore_errors=True)
    os.makedirs(corpus)
    seeds = {
        "pi16": session(THESIS_5FINGER, play(0, False, 16), clear(), target(0, 1200), ticks(400),
                        target(0, 300), ticks(300), target(0, 0), ticks(200)),
        "api8": session(THESIS_5FINGER, play(1, True, 8), clear(), target(1, 900), ticks(300),
                        target(1, 100), ticks(300)),
        "branch_jamming": session(THESIS_5FINGER, branch(3, 6), clear(), target(3, 500),
                                  ticks(300), target(3, 50), ticks(300)),
        "edited_record": session(FULL_8, [4, 3, 2, 8, 0, 0x40, 12, 0, 0x01, 1], ticks(100), target(0, 800),
                                 ticks(200)),
        "update": session(THESIS_5FINGER, target(0, 800), ticks(100), update(3), ticks(50)),
        "valid_image": session(THESIS_5FINGER, target(0, 800), ticks(100), whole_image(200, 3),
                               ticks(50), update_op(4, slot=0), ticks(20)),
        "rolled_back_image": session(THESIS_5FINGER, whole_image(100, 1), ticks(20)),
        "silence_and_estop": session(THESIS_5FINGER, target(0, 800), ticks(100),
                                     [6, 3, 0x10, 0x27], ticks(100), [6, 1, 1, 0], ticks(50),
                                     clear(), ticks(50)),
        "close_release_busy": session(THESIS_5FINGER, target(0, 800), ticks(100), end_session(2, other=5),
                                      end_session(0, foreign=True, other=1), end_session(1), ticks(50),
                                      target(0, 600), ticks(100), end_session(3), ticks(50), connect(),
                                      target(1, 700), ticks(50), end_session(0)),
        "close_during_update": session(THESIS_5FINGER, target(0, 800), ticks(50), update(2), end_session(0),
                                       connect(), update_op(0), ticks(20)),
    }
    for name, data in seeds.items():
        with open(os.path.join(corpus, name), "wb") as f:
            f.write(data)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""palpa from Python: open a simulated board, set fingers, watch their outputs while doing other
work, record, play a scene, E-stop. Fingers are numbered from 0 here, as in C and C++."""
import os
import sys
import tempfile
import time

import palpa


def main():
    with palpa.Device("sim:thesis-5finger") as board:
        info = board.info()
        print(f"{info['config']}: {len(info['fingers'])} fingers: {', '.join(info['fingers'])}")

        board.set(0, level=2)            # pneumatic finger 0: level 2 (30 kPa through its curve)
        board.set(3, n_per_mm=1.0)       # jamming finger 3: 1.0 N/mm
        try:
            board.set(0, n_per_mm=1.0)   # N/mm means nothing for a pneumatic finger
        except palpa.PalpaError as e:
            print(f"refused as it should be: {e}")

        # The fingers re-home first (about 350 ms), then move: drain telemetry without waiting
        # (seconds=0) while doing other work, for a second.
        last = None
        end = time.monotonic() + 1.0
        while time.monotonic() < end:
            for sample in board.monitor(seconds=0):
                last = sample
            time.sleep(0.02)
        outputs = ", ".join(f"{v:.3f} {u}" for v, u in zip(last["finger_output"], last["finger_unit"]))
        print(f"finger outputs: {outputs}")
        print(f"faults: {palpa.bit_names(last['fault_bitmap'], palpa.FAULT_BITS) or 'none'}")
        if not 0.9 < last["finger_output"][0] < 1.5:
            print("finger 0 did not reach level 2", file=sys.stderr)
            return 1

        path = os.path.join(tempfile.mkdtemp(), "run.csv")
        board.record(path, seconds=0.5)
        with open(path) as f:
            f.readline()                 # the JSON header
            print(f"recorded to {path}: {f.readline().strip()[:80]}...")

        # Several fingers at once without waiting (latest-wins): one frame, applied on one tick;
        # the second call replaces the first if the board has not applied it yet.
        board.set_fingers([(0, "level", 1), (1, "level", 2)])
        board.set_fingers([(0, "level", 2), (1, "level", 1)])

        # A scene: the thesis's three fingers on the three-cube phantom, fed a short pass across
        # cube B without waiting (every finger in one frame); each feed says what each touched.
        scene_file = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scene_three_cube.json")
        with palpa.Scene(board, scene_file) as scene:
            for step in range(31):
                renders = scene.feed(45 + step, 12, 1.0, time_s=step * 0.02)
                time.sleep(0.02)
            print("scene at x = 75 mm: " + ", ".join(f"finger {r['finger']} {r['target']:.3f} {r['unit']}"
                                                   for r in renders))
        board.estop()
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""CTest for the Python module: open a simulated board through the C ABI, read info, set fingers,
monitor telemetry (and drain it without waiting), record, EStop, and get clear errors for wrong
requests — checked in Python, naming the finger as the caller numbered it, before anything is sent;
read and change the configuration; a calibration file that agrees with the board's static inverse
(no warning) and one edited beyond its residual (a warning naming both); calibrate a finger on
palpa-sim's rig."""
import json
import os
import shutil
import sys
import tempfile
import time

from palpa_checks import palpa, refused, REPO

DATA = os.path.join(REPO, "tests", "host", "lib", "data")


def curve_warnings(name):
    """The warnings of a simulated board opened with PN-1.json the test data file `name`."""
    directory = tempfile.mkdtemp()
    shutil.copyfile(os.path.join(DATA, name), os.path.join(directory, "PN-1.json"))
    os.environ["PALPA_CALIBRATION_DIR"] = directory
    try:
        with palpa.Device("sim:thesis-5finger") as board:
            return directory, board.curve_warnings()
    finally:
        del os.environ["PALPA_CALIBRATION_DIR"]


def curves():
    _, warnings = curve_warnings("curve_on_board.json")
    assert warnings == [], warnings
    directory, warnings = curve_warnings("curve_off_board.json")
    assert len(warnings) == 1, warnings
    w = warnings[0]
    assert w["finger"] == 0 and w["file"] == os.path.join(directory, "PN-1.json"), w
    assert w["disagreement"] == 40 and w["at_kpa"] == 70.083 and w["residual"] == 12, w
    assert w["unit"] == "µm" and "the nominal one" in w["board"], w
    assert w["file"] in w["message"] and w["board"] in w["message"], w


def main():
    with palpa.Device("sim:thesis-5finger") as board:
        info = board.info()
        assert info["config"] == "thesis-5finger", info
        assert info["fingers"] == ["pneumatic"] * 3 + ["jamming"] * 2, info
        assert info["plant_simulated"] and info["catalog_matches"], info

        board.set(0, level=2)
        board.set(3, n_per_mm=1.0)
        board.set(1, mm=0.5)
        # The library's refusals name the finger as Python numbers it (from 0).
        refused(palpa.PalpaError, lambda: board.set(0, n_per_mm=1.0), "bad_value", "finger 0", "pneumatic")
        refused(palpa.PalpaError, lambda: board.set(0, level=7), "out_of_range", "finger 0")
        # Values a C type would have wrapped or truncated are refused before the call.
        refused(ValueError, lambda: board.set(256, level=1), "finger 256 does not exist", "0 to 4")
        refused(ValueError, lambda: board.set(-1, level=1), "finger -1 does not exist")
        refused(ValueError, lambda: board.set(1, level=2**32 + 2), "finger 1", "level 4294967298")
        refused(TypeError, lambda: board.set(1, level=1.7), "finger 1", "level must be an int")
        refused(TypeError, lambda: board.set(1.0, level=1), "finger must be an int")
        refused(TypeError, lambda: board.set(True, level=1), "finger must be an int")
        refused(TypeError, lambda: board.set(1, mm="0.5"), "finger 1", "mm must be a number")
        refused(ValueError, lambda: board.set(1, mm=float("nan")), "finger 1", "finite")

        samples = list(board.monitor(seconds=1.5))
        assert len(samples) > 500, len(samples)
        last = samples[-1]
        assert last["fault_bitmap"] == 0, last
        assert last["setpoint_pa"][0] > 20000, last  # level 2 = 30 kPa, reached after homing and slew
        # Each finger's output in its unit: finger 0 at level 2 (30 kPa) is about 1.2 mm on the
        # nominal curve; finger 3 at 1.0 N/mm.
        assert last["finger_unit"] == ["mm"] * 3 + ["N/mm"] * 2, last
        assert 0.9 < last["finger_output"][0] < 1.5, last
        assert 0.9 < last["finger_output"][3] < 1.1, last

        # seconds=0 drains what is queued and returns at once: after a pause, what arrived; right
        # after a drain, (almost) nothing.
        time.sleep(0.2)
        queued = list(board.monitor(seconds=0))
        assert len(queued) > 50, len(queued)
        again = list(board.monitor(seconds=0))
        assert len(again) < len(queued), (len(again), len(queued))
        assert board.samples_dropped() == 0
        assert palpa.bit_names(palpa.FAULT_BITS["estop_command"] | 1 << 20, palpa.FAULT_BITS) == \
            ["estop_command", "bit_20"]

        path = os.path.join(tempfile.mkdtemp(), "run.csv")
        board.record(path, 0.3)
        with open(path) as f:
            header = json.loads(f.readline()[2:])
            columns = f.readline().strip().split(",")
            rows = f.readlines()
        assert header["configuration"] == "thesis-5finger", header
        assert columns[:2] == ["utc_time", "board_time_us"], columns
        assert len(rows) > 100, len(rows)

        board.estop()

        # The configuration as palpa config shows it; a change laid over it and read back; a
        # refusal that names the field, with nothing sent.
        config = board.config()
        assert config["board"]["host_timeout_us"] == 100000, config["board"]
        assert len(config["fingers"]) == 5, config
        board.apply_config({"board": {"host_timeout_us": 120000}})
        assert board.config()["board"]["host_timeout_us"] == 120000
        refused(palpa.PalpaError, lambda: board.apply_config({"lines": [{"line": 0, "slew": 1}]}),
                "invalid_argument", "slew", "nothing was sent")
        assert board.config()["board"]["host_timeout_us"] == 120000

    curves()

    # A quick calibration on palpa-sim's rig, as palpa calibrate --rig sim --quick runs it, at the
    # simulator's top speed: this holds the Python call and its files, not the rig (palpa-sim
    # judges the host's silence in real time too, so a loaded host keeps its 100 ms).
    out = tempfile.mkdtemp()
    summary = palpa.calibrate_simulated(1, out, quick=True, compensator="api", sim={"seed": 2, "speed": 10})
    assert summary["calibrated"] == "PN-2" and summary["finger"] == 1, summary
    assert summary["compensator"] == "api(8)", summary
    assert sorted(os.listdir(out)) == ["PN-2.csv", "PN-2.html", "PN-2.json"], os.listdir(out)
    with open(os.path.join(out, "PN-2.json")) as f:
        assert json.load(f)["simulation"]["seed"] == 2
    refused(palpa.PalpaError, lambda: palpa.calibrate_simulated(1, out, compensator="branch"),
            "invalid_argument", "compensator")
    try:
        palpa.Device("tcp:127.0.0.1:1")
        raise AssertionError("opening nothing must fail")
    except palpa.PalpaError as e:
        assert "tcp:127.0.0.1:1" in str(e), e
    print("1 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

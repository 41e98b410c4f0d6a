"""palpa for Python: a ctypes wrapper over the palpa C ABI (libpalpa.so).

    import palpa
    with palpa.Device("sim:thesis-5finger") as board:
        print(board.info())
        board.set(0, level=2)            # finger 0 to level 2 (fingers numbered from 0)
        board.set(3, n_per_mm=1.0)       # a jamming finger
        for sample in board.monitor(seconds=1.0):
            print(sample["measured_pa"], sample["finger_output"])
    # leaving the block closes the session: every output safe at once, no fault latched

palpa.Device("serve:127.0.0.1:7180") reaches a board behind a running `palpa serve` instead, with
the same methods: several programs watch one board while one controls it (palpa/serve.py).

A refusal raises PalpaError: .status names it ("faulted", "busy", ...); for latched faults
.faults lists them ("host_silence", ...) and the message says when each latched and what to do.

The library is found through $PALPA_LIBRARY, then where the install put it beside this package,
then the system's library path.
"""
import ctypes
import json
import math
import numbers
import os
import time

from ._bits import FAULT_BITS, LINE_STATUS_BITS, bit_names  # noqa: F401  (public names)
from ._native import MAX_FINGERS, MAX_LINES, _Info, _library, _Request, _Sample  # noqa: F401

_INT_MAX = 2**31 - 1
QUEUE_LIMIT = 65536  # PALPA_SAMPLE_QUEUE_LIMIT
_UNITS = ("mm", "N/mm")


def _sample_dict(s):
    lines, fingers = s.line_count, s.finger_count
    return {"board_time_us": s.board_time_us, "host_time_s": s.host_time_s,
            "setpoint_pa": list(s.setpoint_pa[:lines]), "measured_pa": list(s.measured_pa[:lines]),
            "command_counts": list(s.command_counts[:lines]), "status": list(s.status[:lines]),
            "fault_bitmap": s.fault_bitmap,
            "finger_output": list(s.finger_output[:fingers]),
            "finger_unit": [_UNITS[u] for u in s.finger_unit[:fingers]]}


class PalpaError(Exception):
    """A palpa call failed: .status is the shared status name, the message says why; .faults
    names the latched faults it was refused for (empty when it was not)."""

    def __init__(self, status, message, faults=()):
        super().__init__(f"{status}: {message}")
        self.status = status
        self.faults = list(faults)


def _fault_names(lib, bitmap):
    return [lib.palpa_fault_name(bit).decode() for bit in range(32) if bitmap & (1 << bit)]


def _text_call(call, check, capacity=64 * 1024, again=True):
    """A C call that copies JSON text out (palpa.h); with `again`, called again with a larger
    buffer when the text did not fit."""
    while True:
        buffer, length = ctypes.create_string_buffer(capacity), ctypes.c_size_t()
        status = call(buffer, capacity, ctypes.byref(length))
        if again and status == 14 and length.value >= capacity:  # PALPA_STATUS_OVERFLOW
            capacity = length.value + 1
            continue
        check(status)
        return json.loads(buffer.value.decode())


def _calibrate(lib, handle, rig, finger, out, options, check):
    options = dict(options, finger=finger, out=os.fspath(out))
    # A summary is a few KiB: a calibration is never run twice for a larger buffer.
    return _text_call(lambda b, n, length: lib.palpa_calibrate(
        handle, rig.encode(), json.dumps(options).encode(), b, n, length), check,
        capacity=1024 * 1024, again=False)


def calibrate_simulated(finger, out, **options):
    """Calibrates finger `finger` (from 0) of a simulated board on palpa-sim's rig, as
    `palpa calibrate --rig sim` does, writing SERIAL.json, .csv and .html to `out`; returns the
    summary (files, compensator, residual, checks). Options as palpa_calibrate's JSON (palpa.h):
    quick, protocol, compensator, operators, allow_fallback, resume, previous, and
    sim={"config", "speed", "unit", "seed", "plant", "effects"}."""
    lib = _library()

    def check(status):
        if status != 0:
            raise PalpaError(lib.palpa_status_name(status).decode(), lib.palpa_last_error(None).decode())
    return _calibrate(lib, None, "sim", finger, out, options, check)


class _Closable:
    """Something the library opened and must be given back once: close() does it, so does
    leaving a `with` block (exceptions included) and garbage collection of a forgotten one.
    Subclasses set self._handle and say in _release(handle) how it is given back."""
    _handle = None

    def _release(self, handle):
        raise NotImplementedError

    def close(self):
        if self._handle:
            self._release(self._handle)
            self._handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the board's timeout ends a session instead
            pass


class Device(_Closable):
    """One palpa board. close() (or `with`) ends the session: every output safe at once, no fault
    latched, the board free for the next host. "serve:HOST:PORT" reaches one behind a running
    `palpa serve` instead (a ServeDevice, palpa/serve.py: the same methods, control taken by the
    first call that acts, given up by close())."""

    def __new__(cls, uri):
        if isinstance(uri, str) and uri.startswith("serve:"):
            from .serve import ServeDevice
            return ServeDevice(uri)
        return super().__new__(cls)

    def __init__(self, uri):
        lib = _library()
        handle = ctypes.c_void_p()
        status = lib.palpa_open(uri.encode(), ctypes.byref(handle))
        if status != 0:
            raise PalpaError(lib.palpa_status_name(status).decode(), lib.palpa_last_error(None).decode())
        self._lib, self._handle = lib, handle

    def _check(self, status):
        if status != 0:
            if not self._handle:
                raise PalpaError("no_session", "the device is closed")
            raise PalpaError(self._lib.palpa_status_name(status).decode(),
                             self._lib.palpa_last_error(self._handle).decode(),
                             _fault_names(self._lib, self._lib.palpa_last_faults(self._handle)))

    def _release(self, handle):
        """Ends the session: every output safe at once, no fault latched, the board free for the
        next host."""
        self._lib.palpa_close(handle)

    def info(self):
        info = _Info()
        self._check(self._lib.palpa_get_info(self._handle, ctypes.byref(info)))
        return {
            "board_id": info.board_id,
            "firmware": f"{info.firmware_major}.{info.firmware_minor}.{info.firmware_patch}",
            "catalog_hash": info.catalog_hash,
            "catalog_matches": bool(info.catalog_matches),
            "plant_simulated": bool(info.plant_simulated),
            "time_scale": info.time_scale,
            "config": info.config_name.decode(),
            "lines": info.line_count,
            "fingers": ["jamming" if info.finger_kind[f] else "pneumatic" for f in range(info.finger_count)],
            "fault_bitmap": info.fault_bitmap,
        }

    def set(self, finger, level=None, normalized=None, n_per_mm=None, mm=None, kpa=None):
        """Sets one finger (numbered from 0) to exactly one of: a level (an int), normalized
        stiffness 0..1, n_per_mm (jamming fingers), mm (pneumatic fingers) or kpa (raw mode).

        Returns once the board applied it. Applied is not yet moved: a finger leaving its safe
        state (the first target after opening or clear_fault, or after kpa) re-homes first for
        the board's homing dwell (board.home_dwell_ms, 300 ms by default), so it starts to move
        about 350 ms later. Wrong types raise TypeError, a finger or level that cannot exist
        ValueError (before anything is sent); the board's and the library's refusals raise
        PalpaError."""
        given = {k: v for k, v in (("level", level), ("normalized", normalized), ("n_per_mm", n_per_mm),
                                    ("mm", mm), ("kpa", kpa)) if v is not None}
        if len(given) != 1:
            raise ValueError("set() takes exactly one of level, normalized, n_per_mm, mm, kpa")
        (kind, value), = given.items()
        finger = self._finger_index(finger)
        if kind == "level":
            if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                raise TypeError(f"finger {finger}: level must be an int, not {type(value).__name__} "
                                f"({value!r})")
            if not 0 <= value <= _INT_MAX:
                raise ValueError(f"finger {finger}: level {value} does not exist (levels are 0, 1, 2 ...)")
            value = int(value)
        else:
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"finger {finger}: {kind} must be a number, not {type(value).__name__}")
            value = float(value)
            if not math.isfinite(value):
                raise ValueError(f"finger {finger}: {kind} must be finite, not {value}")
        call = {"level": self._lib.palpa_set_level, "normalized": self._lib.palpa_set_normalized,
                "n_per_mm": self._lib.palpa_set_stiffness, "mm": self._lib.palpa_set_deformation,
                "kpa": self._lib.palpa_set_pressure}[kind]
        self._check(call(self._handle, finger, value))

    _KINDS = {"level": 0, "normalized": 1, "n_per_mm": 2, "mm": 3, "kpa": 4}  # PALPA_TARGET_*

    def set_fingers(self, requests, wait=False):
        """Several fingers at once, in one frame (the board applies them on one tick): requests
        is a list of (finger, kind, value), kind one of "level", "normalized", "n_per_mm", "mm",
        "kpa". wait=False returns once the frame is sent (latest-wins: a later call replaces one
        the board has not applied yet); wait=True once the board applied it. Every request is
        checked before anything is sent."""
        if not 1 <= len(requests) <= MAX_FINGERS:
            raise ValueError(f"set_fingers takes 1 to {MAX_FINGERS} requests, not {len(requests)}")
        array = (_Request * len(requests))()
        for i, (finger, kind, value) in enumerate(requests):
            if kind not in self._KINDS:
                raise ValueError(f"requests[{i}]: kind {kind!r} is not one of {', '.join(self._KINDS)}")
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"requests[{i}]: value must be a finite number, not {value!r}")
            array[i] = _Request(self._finger_index(finger), self._KINDS[kind], float(value))
        self._check(self._lib.palpa_set_fingers(self._handle, array, len(requests), 1 if wait else 0))

    def _finger_index(self, finger):
        """The finger as an index the C ABI takes: an int within this board's fingers."""
        if isinstance(finger, bool) or not isinstance(finger, numbers.Integral):
            raise TypeError(f"finger must be an int (numbered from 0), not {type(finger).__name__} "
                            f"({finger!r})")
        count = len(self.info()["fingers"])
        if not 0 <= finger < count:
            raise ValueError(f"finger {finger} does not exist: this board has fingers 0 to {count - 1}")
        return int(finger)

    def estop(self):
        self._check(self._lib.palpa_estop(self._handle))

    def clear_fault(self):
        self._check(self._lib.palpa_clear_fault(self._handle))

    def release(self):
        """Every output safe at once, no fault latched; the session stays and set() actuates
        again."""
        self._check(self._lib.palpa_release(self._handle))

    def monitor(self, seconds=1.0):
        """Yields telemetry samples (dicts), one per board tick, for `seconds`; seconds=0 yields
        the samples queued since the last call and returns without waiting (a drain for a loop
        that does other work). The library queues up to QUEUE_LIMIT samples between calls and
        drops the oldest beyond that (samples_dropped() counts them)."""
        if isinstance(seconds, bool) or not isinstance(seconds, numbers.Real) or not seconds >= 0:
            raise ValueError(f"seconds must be a number 0 or more, not {seconds!r}")
        buffer = (_Sample * 256)()
        end = time.monotonic() + seconds
        while True:
            wait_ms = 0 if seconds == 0 else max(0, min(50, int((end - time.monotonic()) * 1000)))
            n = self._lib.palpa_read_samples(self._handle, buffer, 256, wait_ms)
            if n < 0:
                self._check(-n)
            for s in buffer[:n]:
                yield _sample_dict(s)
            if seconds == 0 and n < 256:
                return
            if seconds > 0 and time.monotonic() >= end:
                return

    def samples_dropped(self):
        """Samples dropped from the full queue since the device was opened."""
        return self._lib.palpa_samples_dropped(self._handle)

    def record(self, path, seconds):
        """Records telemetry to a CSV file (JSON header line first) for `seconds`."""
        self._check(self._lib.palpa_record_start(self._handle, path.encode()))
        try:
            time.sleep(seconds)
        finally:
            self._check(self._lib.palpa_record_stop(self._handle))

    def config(self):
        """The board's whole live configuration, as `palpa config show` prints it (lines and
        fingers numbered from 0)."""
        return _text_call(lambda b, n, length: self._lib.palpa_config_read(self._handle, b, n, length),
                          self._check)

    def apply_config(self, patch):
        """Lays a (partial) configuration, in config()'s shape, over the live one: checked field
        by field and as the board would, then applied all at once or not at all. Not saved."""
        self._check(self._lib.palpa_config_apply(self._handle, json.dumps(patch).encode()))

    def save_config(self):
        """Keeps the live configuration across resets."""
        self._check(self._lib.palpa_config_save(self._handle))

    def curve_warnings(self):
        """Calibration files that disagree with the static inverse their finger's board holds by
        more than their fit residual: [{"finger", "file", "board", "disagreement", "at_kpa",
        "residual", "unit", "message"}] (fingers from 0). Such a finger follows the board's curve."""
        return _text_call(lambda b, n, length: self._lib.palpa_curve_warnings(self._handle, b, n, length),
                          self._check)

    def calibrate(self, rig_file, finger, out, **options):
        """Calibrates finger `finger` (from 0) of this board on the rig `rig_file` names, as
        `palpa calibrate --rig FILE` does; options and result as calibrate_simulated's."""
        return _calibrate(self._lib, self._handle, os.fspath(rig_file), finger, out, options, self._check)


from .scene import Scene, Tablet  # noqa: E402  (it uses what is defined above)

"""palpa for Python: a ctypes wrapper over the palpa C ABI (libpalpa.so).

    import palpa
    with palpa.Device("sim:thesis-5finger") as board:
        print(board.info())
        board.set(0, level=2)            # finger 0 to level 2
        board.set(3, n_per_mm=1.0)       # a jamming finger
        for sample in board.monitor(seconds=1.0):
            print(sample["measured_pa"])
        board.estop()

The library is found through $PALPA_LIBRARY, then the system's library path.
"""
import ctypes
import ctypes.util
import os
import time

MAX_LINES = 8
MAX_FINGERS = 8


class _Info(ctypes.Structure):
    _fields_ = [
        ("board_id", ctypes.c_uint32),
        ("firmware_major", ctypes.c_uint8),
        ("firmware_minor", ctypes.c_uint8),
        ("firmware_patch", ctypes.c_uint8),
        ("board_kind", ctypes.c_uint8),
        ("catalog_hash", ctypes.c_uint32),
        ("catalog_matches", ctypes.c_int),
        ("plant_simulated", ctypes.c_int),
        ("time_scale", ctypes.c_float),
        ("config_name", ctypes.c_char * 25),
        ("line_count", ctypes.c_uint8),
        ("finger_count", ctypes.c_uint8),
        ("finger_kind", ctypes.c_uint8 * MAX_FINGERS),
        ("fault_bitmap", ctypes.c_uint32),
    ]


class _Sample(ctypes.Structure):
    _fields_ = [
        ("board_time_us", ctypes.c_uint64),
        ("host_time_s", ctypes.c_double),
        ("line_count", ctypes.c_uint8),
        ("setpoint_pa", ctypes.c_int32 * MAX_LINES),
        ("measured_pa", ctypes.c_int32 * MAX_LINES),
        ("command_counts", ctypes.c_uint16 * MAX_LINES),
        ("status", ctypes.c_uint8 * MAX_LINES),
        ("fault_bitmap", ctypes.c_uint32),
    ]


def _load():
    path = os.environ.get("PALPA_LIBRARY") or ctypes.util.find_library("palpa")
    if not path:
        raise OSError("libpalpa not found: set PALPA_LIBRARY to the path of libpalpa.so")
    lib = ctypes.CDLL(path)
    lib.palpa_open.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.palpa_close.argtypes = [ctypes.c_void_p]
    lib.palpa_last_error.argtypes = [ctypes.c_void_p]
    lib.palpa_last_error.restype = ctypes.c_char_p
    lib.palpa_status_name.argtypes = [ctypes.c_int]
    lib.palpa_status_name.restype = ctypes.c_char_p
    lib.palpa_get_info.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Info)]
    for name, arg in (("palpa_set_level", ctypes.c_int), ("palpa_set_normalized", ctypes.c_double),
                      ("palpa_set_stiffness", ctypes.c_double), ("palpa_set_deformation", ctypes.c_double),
                      ("palpa_set_pressure", ctypes.c_double)):
        getattr(lib, name).argtypes = [ctypes.c_void_p, ctypes.c_uint8, arg]
    lib.palpa_estop.argtypes = [ctypes.c_void_p]
    lib.palpa_clear_fault.argtypes = [ctypes.c_void_p]
    lib.palpa_read_samples.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Sample), ctypes.c_int, ctypes.c_int]
    lib.palpa_record_start.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    lib.palpa_record_stop.argtypes = [ctypes.c_void_p]
    return lib


_lib = None


def _library():
    global _lib
    if _lib is None:
        _lib = _load()
    return _lib


class PalpaError(Exception):
    """A palpa call failed: .status is the shared status name, the message says why."""

    def __init__(self, status, message):
        super().__init__(f"{status}: {message}")
        self.status = status


class Device:
    """One palpa board."""

    def __init__(self, uri):
        lib = _library()
        handle = ctypes.c_void_p()
        status = lib.palpa_open(uri.encode(), ctypes.byref(handle))
        if status != 0:
            raise PalpaError(lib.palpa_status_name(status).decode(), lib.palpa_last_error(None).decode())
        self._lib, self._handle = lib, handle

    def _check(self, status):
        if status != 0:
            raise PalpaError(self._lib.palpa_status_name(status).decode(),
                             self._lib.palpa_last_error(self._handle).decode())

    def close(self):
        if self._handle:
            self._lib.palpa_close(self._handle)
            self._handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

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
        """Sets one finger; exactly one of the keyword arguments."""
        given = {k: v for k, v in (("level", level), ("normalized", normalized), ("n_per_mm", n_per_mm),
                                    ("mm", mm), ("kpa", kpa)) if v is not None}
        if len(given) != 1:
            raise ValueError("set() takes exactly one of level, normalized, n_per_mm, mm, kpa")
        (kind, value), = given.items()
        call = {"level": self._lib.palpa_set_level, "normalized": self._lib.palpa_set_normalized,
                "n_per_mm": self._lib.palpa_set_stiffness, "mm": self._lib.palpa_set_deformation,
                "kpa": self._lib.palpa_set_pressure}[kind]
        self._check(call(self._handle, finger, int(value) if kind == "level" else float(value)))

    def estop(self):
        self._check(self._lib.palpa_estop(self._handle))

    def clear_fault(self):
        self._check(self._lib.palpa_clear_fault(self._handle))

    def monitor(self, seconds=1.0):
        """Yields telemetry samples (dicts) for `seconds`."""
        buffer = (_Sample * 256)()
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            n = self._lib.palpa_read_samples(self._handle, buffer, 256, 50)
            if n < 0:
                self._check(-n)
            for s in buffer[:n]:
                lines = s.line_count
                yield {"board_time_us": s.board_time_us, "host_time_s": s.host_time_s,
                       "setpoint_pa": list(s.setpoint_pa[:lines]), "measured_pa": list(s.measured_pa[:lines]),
                       "command_counts": list(s.command_counts[:lines]), "status": list(s.status[:lines]),
                       "fault_bitmap": s.fault_bitmap}

    def record(self, path, seconds):
        """Records telemetry to a CSV file (JSON header line first) for `seconds`."""
        self._check(self._lib.palpa_record_start(self._handle, path.encode()))
        try:
            time.sleep(seconds)
        finally:
            self._check(self._lib.palpa_record_stop(self._handle))

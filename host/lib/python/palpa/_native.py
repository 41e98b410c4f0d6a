"""The C ABI as ctypes sees it: the structures palpa.h declares, and libpalpa found and loaded
once, with every function's argument and result types."""
import ctypes
import ctypes.util
import os

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
        ("finger_count", ctypes.c_uint8),
        ("finger_output", ctypes.c_double * MAX_FINGERS),
        ("finger_unit", ctypes.c_uint8 * MAX_FINGERS),
    ]


class _Request(ctypes.Structure):
    _fields_ = [("finger", ctypes.c_uint8), ("kind", ctypes.c_int), ("value", ctypes.c_double)]


def _library_path():
    """$PALPA_LIBRARY, else the library installed with this package, else the system's."""
    if os.environ.get("PALPA_LIBRARY"):
        return os.environ["PALPA_LIBRARY"]
    here = os.path.dirname(os.path.abspath(__file__))
    candidates = [os.path.join(here, "libpalpa.so.0")]
    try:
        from . import _installed  # written by the install: the library relative to this package
        candidates.append(os.path.normpath(os.path.join(here, _installed.LIBRARY)))
    except ImportError:
        pass
    for candidate in candidates:
        if os.path.exists(candidate):
            return candidate
    return ctypes.util.find_library("palpa")


def _load():
    path = _library_path()
    if not path:
        raise OSError("libpalpa not found: install palpa (cmake --install) or set PALPA_LIBRARY to "
                      "the path of libpalpa.so")
    lib = ctypes.CDLL(path)
    lib.palpa_open.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.palpa_close.argtypes = [ctypes.c_void_p]
    lib.palpa_last_error.argtypes = [ctypes.c_void_p]
    lib.palpa_last_error.restype = ctypes.c_char_p
    lib.palpa_last_faults.argtypes = [ctypes.c_void_p]
    lib.palpa_last_faults.restype = ctypes.c_uint32
    lib.palpa_fault_name.argtypes = [ctypes.c_int]
    lib.palpa_fault_name.restype = ctypes.c_char_p
    lib.palpa_status_name.argtypes = [ctypes.c_int]
    lib.palpa_status_name.restype = ctypes.c_char_p
    lib.palpa_get_info.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Info)]
    for name, arg in (("palpa_set_level", ctypes.c_int), ("palpa_set_normalized", ctypes.c_double),
                      ("palpa_set_stiffness", ctypes.c_double), ("palpa_set_deformation", ctypes.c_double),
                      ("palpa_set_pressure", ctypes.c_double)):
        getattr(lib, name).argtypes = [ctypes.c_void_p, ctypes.c_uint8, arg]
    lib.palpa_estop.argtypes = [ctypes.c_void_p]
    lib.palpa_clear_fault.argtypes = [ctypes.c_void_p]
    lib.palpa_release.argtypes = [ctypes.c_void_p]
    lib.palpa_read_samples.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Sample), ctypes.c_int, ctypes.c_int]
    lib.palpa_samples_dropped.argtypes = [ctypes.c_void_p]
    lib.palpa_samples_dropped.restype = ctypes.c_uint64
    lib.palpa_record_start.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    lib.palpa_record_stop.argtypes = [ctypes.c_void_p]
    lib.palpa_config_read.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t,
                                      ctypes.POINTER(ctypes.c_size_t)]
    lib.palpa_config_apply.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    lib.palpa_config_save.argtypes = [ctypes.c_void_p]
    lib.palpa_curve_warnings.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t,
                                         ctypes.POINTER(ctypes.c_size_t)]
    lib.palpa_calibrate.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p,
                                    ctypes.c_size_t, ctypes.POINTER(ctypes.c_size_t)]
    lib.palpa_set_fingers.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Request), ctypes.c_int, ctypes.c_int]
    return lib


_lib = None


def _library():
    global _lib
    if _lib is None:
        _lib = _load()
    return _lib

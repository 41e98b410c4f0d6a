"""Scenes from Python (docs/scenes.md): a virtual tissue rendered to the fingers as a hand
explores it. Feed samples at your own rate; each goes out without waiting, every finger in one
frame.

    with palpa.Device("sim:thesis-pneumatic-3") as board:
        scene = palpa.Scene(board, "scene_three_cube.json")
        for t, x, y, force in samples:
            renders = scene.feed(x, y, force, time_s=t)   # one dict per finger
        for sample in board.monitor(seconds=0):          # telemetry, drained without waiting
            ...
"""
import ctypes
import numbers

from . import _library, _Closable, MAX_FINGERS, _UNITS


class _Render(ctypes.Structure):
    _fields_ = [
        ("finger", ctypes.c_uint8),
        ("touching", ctypes.c_int),
        ("value", ctypes.c_double),
        ("depth_mm", ctypes.c_double),
        ("u", ctypes.c_double),
        ("target", ctypes.c_double),
        ("finger_unit", ctypes.c_uint8),
    ]


def _declare(lib):
    if getattr(lib, "_palpa_scene_declared", False):
        return
    lib.palpa_scene_open.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.palpa_scene_feed.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_double,
                                     ctypes.c_double, ctypes.POINTER(_Render), ctypes.c_int]
    lib.palpa_scene_close.argtypes = [ctypes.c_void_p]
    lib._palpa_scene_declared = True


def _number(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, not {type(value).__name__} ({value!r})")
    return float(value)


class Scene(_Closable):
    """A scene file's scene on an open Device (which must stay open while the scene is used);
    close() or `with` gives it back."""

    def __init__(self, device, path):
        lib = _library()
        _declare(lib)
        handle = ctypes.c_void_p()
        device._check(lib.palpa_scene_open(device._handle, str(path).encode(), ctypes.byref(handle)))
        self._lib, self._device, self._handle = lib, device, handle
        self._renders = (_Render * MAX_FINGERS)()

    def feed(self, x_mm, y_mm, force_n, time_s=0.0):
        """Renders one sample — where the hand is on the tissue (mm), how hard it presses (N) —
        and sends every finger's target in one frame without waiting (latest-wins). Returns one
        dict per finger: finger, touching, value, depth_mm, u, target and unit ("mm" or
        "N/mm"). A force or position that is not a finite number releases the fingers."""
        values = [_number(n, v) for n, v in (("x_mm", x_mm), ("y_mm", y_mm), ("force_n", force_n),
                                            ("time_s", time_s))]
        if not self._handle:
            raise ValueError("the scene is closed")
        x, y, force, t = values
        n = self._lib.palpa_scene_feed(self._handle, t, x, y, force, self._renders, MAX_FINGERS)
        if n < 0:
            self._device._check(-n)
        return [{"finger": r.finger, "touching": bool(r.touching), "value": r.value,
                 "depth_mm": r.depth_mm, "u": r.u, "target": r.target, "unit": _UNITS[r.finger_unit]}
                for r in self._renders[:n]]

    def _release(self, handle):
        self._lib.palpa_scene_close(handle)


__all__ = ["Scene"]

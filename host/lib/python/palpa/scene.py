"""Scenes from Python (docs/scenes.md): a virtual tissue rendered to the fingers as a hand
explores it. Feed samples at your own rate; each goes out without waiting, every finger in one
frame.

    with palpa.Device("sim:thesis-pneumatic-3") as board:
        scene = palpa.Scene(board, "scene_three_cube.json")
        for t, x, y, force in samples:
            renders = scene.feed(x, y, force, time_s=t)   # one dict per finger
        for sample in board.monitor(seconds=0):          # telemetry, drained without waiting
            ...

A pen tablet or touchpad (evdev) feeds it directly, a tactile array's frames are grouped per
finger by the scene file, and prediction renders ahead of the fingers' calibrated delay:

        horizon_s = scene.predict()                      # refused if a finger is uncalibrated
        with palpa.Tablet(scene, "/dev/input/event5") as pen:
            while True:
                sample = pen.next(timeout_ms=50)         # (time_s, x_mm, y_mm, force_n) or None
                if sample:
                    scene.feed(sample[1], sample[2], sample[3], time_s=sample[0])
        scene.feed_tactile(values)                       # one frame of the array; None: soft
"""
import ctypes
import numbers

from . import _library, _Closable, MAX_FINGERS, _UNITS


class _Input(ctypes.Structure):
    _fields_ = [("time_s", ctypes.c_double), ("x_mm", ctypes.c_double), ("y_mm", ctypes.c_double),
                ("force_n", ctypes.c_double)]


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
    lib.palpa_scene_predict.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(ctypes.c_double)]
    lib.palpa_scene_feed_tactile.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double), ctypes.c_int,
                                             ctypes.POINTER(_Render), ctypes.c_int]
    lib.palpa_tablet_open.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.palpa_tablet_next.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(_Input)]
    lib.palpa_tablet_close.argtypes = [ctypes.c_void_p]
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
        return self._result(n)

    def feed_tactile(self, values):
        """Renders one frame of the scene's tactile array (its input.tactile: one value per
        element), each finger's group averaged and mapped by the rule, and sends it as feed does.
        None releases every finger (the stream stalled). Returns the renders as feed does."""
        if not self._handle:
            raise ValueError("the scene is closed")
        if values is None:
            return self._result(self._lib.palpa_scene_feed_tactile(self._handle, None, 0, self._renders,
                                                                   MAX_FINGERS))
        array = (ctypes.c_double * len(values))(*[_number(f"values[{k}]", v) for k, v in enumerate(values)])
        return self._result(self._lib.palpa_scene_feed_tactile(self._handle, array, len(values),
                                                               self._renders, MAX_FINGERS))

    def predict(self, on=True):
        """With on, each feed renders where the hand will be after the fingers' display delay,
        from their lines' calibrated chamber models (PalpaError naming the line when one has
        none). Returns that delay in seconds (None when turned off)."""
        if not self._handle:
            raise ValueError("the scene is closed")
        horizon = ctypes.c_double(0)
        self._device._check(self._lib.palpa_scene_predict(self._handle, 1 if on else 0, ctypes.byref(horizon)))
        return horizon.value if on else None

    def _result(self, n):
        if n < 0:
            self._device._check(-n)
        return [{"finger": r.finger, "touching": bool(r.touching), "value": r.value,
                 "depth_mm": r.depth_mm, "u": r.u, "target": r.target, "unit": _UNITS[r.finger_unit]}
                for r in self._renders[:n]]

    def _release(self, handle):
        self._lib.palpa_scene_close(handle)


class Tablet(_Closable):
    """A pen tablet or touchpad (an evdev node) mapped onto a scene's tissue, its pressure through
    the scene's input.tablet form. A device that is not a pad is refused naming what it lacks;
    close() or `with` gives it back."""

    def __init__(self, scene, path):
        if not scene._handle:
            raise ValueError("the scene is closed")
        handle = ctypes.c_void_p()
        scene._device._check(scene._lib.palpa_tablet_open(scene._handle, str(path).encode(),
                                                         ctypes.byref(handle)))
        self._lib, self._device, self._handle = scene._lib, scene._device, handle

    def next(self, timeout_ms=50):
        """The pad's next report as (time_s, x_mm, y_mm, force_n), or None when none came."""
        if not self._handle:
            raise ValueError("the tablet is closed")
        sample = _Input()
        n = self._lib.palpa_tablet_next(self._handle, int(timeout_ms), ctypes.byref(sample))
        if n < 0:
            self._device._check(-n)
        return (sample.time_s, sample.x_mm, sample.y_mm, sample.force_n) if n == 1 else None

    def _release(self, handle):
        self._lib.palpa_tablet_close(handle)


__all__ = ["Scene", "Tablet"]

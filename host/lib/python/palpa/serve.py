"""A board behind a running `palpa serve` (docs/serve.md): palpa.Device("serve:HOST:PORT") returns
a ServeDevice, which speaks the server's JSON-RPC API over a WebSocket with Python's standard
library only. Several programs watch one board this way while one controls it: reading (info,
diagnostics, configuration, monitor) needs nothing, and the first call that acts on the board
takes control — refused (PalpaError "busy") while another client holds it. Closing gives control
up, and the server then releases the board, as closing a session does.

    with palpa.Device("serve:127.0.0.1:7180") as board:   # "?token=..." beyond loopback
        board.set(0, level=2)
"""
import json
import math
import numbers
import queue
import time
import urllib.parse

from ._websocket import _Connection

_TARGET_KINDS = ("level", "normalized", "n_per_mm", "mm", "kpa")


def _error_class():
    from . import PalpaError  # the package's one error type
    return PalpaError


def _closable():
    from . import _Closable  # close(), `with` and collection, as Device has them
    return _Closable


def parse_serve_uri(uri):
    """"serve:HOST:PORT[?token=T]" as (host, port, token); ValueError naming what is wrong."""
    rest = uri[len("serve:"):]
    rest, _, query = rest.partition("?")
    token = urllib.parse.parse_qs(query).get("token", [""])[0] if query else ""
    host, sep, port = rest.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise ValueError(f"{uri}: expected serve:HOST:PORT (palpa serve's address), e.g. "
                         "serve:127.0.0.1:7180")
    return host, int(port), token


class ServeDevice(_closable()):
    """One board behind `palpa serve`, with Device's methods (fingers and lines from 0). close()
    (or `with`, or collection) gives control up — the server then releases the board — and
    disconnects."""

    def __init__(self, uri):
        host, port, token = parse_serve_uri(uri)
        self.uri = uri
        self._handle = self._conn = _Connection(host, port, token)
        self._next_id = 1
        self._notifications = []
        self._controls = False
        self._board = self._call("board.info")
        self._call("server.connection.identify", client_name="python")

    def _call(self, method, **params):
        if self._conn is None:
            raise _error_class()("no_session", "the device is closed")
        id_ = self._next_id
        self._next_id += 1
        self._conn.send(0x1, json.dumps({"jsonrpc": "2.0", "id": id_, "method": method,
                                         "params": params}).encode())
        deadline = time.monotonic() + 30
        while True:
            try:
                m = self._conn.messages.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise _error_class()("timeout", f"{method}: no answer from palpa serve in 30 s")
            if m is None:
                raise _error_class()("unavailable", f"{method}: palpa serve closed the connection")
            if isinstance(m, dict) and "id" not in m:
                if m.get("method") == "notify_telemetry":  # for monitor(); others are not kept
                    self._notifications.append(m)
                continue
            if isinstance(m, dict) and m.get("id") == id_:
                if "error" in m:
                    e = m["error"]
                    data = e.get("data") or {}
                    status = data.get("status") or {-32001: "busy", -32002: "busy"}.get(
                        e.get("code"), "invalid_argument")
                    raise _error_class()(status, e.get("message", ""), data.get("faults", ()))
                return m["result"]

    def _act(self, method, **params):
        """A call that acts on the board: control taken first (never from another client)."""
        if not self._controls:
            self._call("control.take")
            self._controls = True
        return self._call(method, **params)

    def _release(self, conn):
        try:
            if self._controls:
                self._call("control.release")
        except Exception:
            pass  # the server releases a controller that goes away anyway
        conn.close()
        self._conn = None

    def info(self):
        """As Device.info(): the board's identity, its lines and finger kinds."""
        b = self._call("board.info")
        board = b["board"]
        return {"board_id": board["id"], "firmware": board["firmware"],
                "catalog_hash": board["catalog_hash"], "catalog_matches": board["catalog_matches"],
                "plant_simulated": board["plant_simulated"], "time_scale": board["time_scale"],
                "config": board["configuration"], "lines": len(b["lines"]),
                "fingers": [f["kind"] for f in b["fingers"]], "fault_bitmap": board["fault_bitmap"],
                "device": b["device"]}

    def diagnostics(self):
        """As `palpa --json diag` prints them (lines from 0)."""
        return self._call("board.diagnostics")

    def set(self, finger, level=None, normalized=None, n_per_mm=None, mm=None, kpa=None):
        """As Device.set(): exactly one unit, returns once the board applied it."""
        given = {k: v for k, v in (("level", level), ("normalized", normalized), ("n_per_mm", n_per_mm),
                                    ("mm", mm), ("kpa", kpa)) if v is not None}
        if len(given) != 1:
            raise ValueError("set() takes exactly one of level, normalized, n_per_mm, mm, kpa")
        (kind, value), = given.items()
        self.set_fingers([(finger, kind, value)], wait=True)

    def set_fingers(self, requests, wait=False):
        """As Device.set_fingers(); through the server a set always returns once applied."""
        targets = []
        for i, (finger, kind, value) in enumerate(requests):
            if kind not in _TARGET_KINDS:
                raise ValueError(f"requests[{i}]: kind {kind!r} is not one of {', '.join(_TARGET_KINDS)}")
            if isinstance(finger, bool) or not isinstance(finger, numbers.Integral):
                raise TypeError(f"finger must be an int (numbered from 0), not {finger!r}")
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"requests[{i}]: value must be a finite number, not {value!r}")
            if kind == "level" and not isinstance(value, numbers.Integral):
                raise TypeError(f"finger {finger}: level must be an int, not {value!r}")
            count = len(self._board["fingers"])
            if not 0 <= finger < count:
                raise ValueError(f"finger {finger} does not exist: this board has fingers 0 to {count - 1}")
            targets.append({"finger": int(finger), kind: value})
        self._act("board.set", targets=targets)

    def estop(self):
        """Every line safe: anyone may, controlling or not."""
        self._call("board.estop")

    def clear_fault(self):
        self._act("board.clear")

    def release(self):
        self._act("board.release")

    def monitor(self, seconds=1.0, sample_rate_hz=1000):
        """Yields telemetry samples as Device.monitor() does, thinned by the server to
        `sample_rate_hz` (1 kHz: every sample of a board at its default rate) for `seconds`."""
        sub = self._call("telemetry.subscribe", updates_per_s=30, sample_rate_hz=sample_rate_hz)
        end = time.monotonic() + seconds
        try:
            while True:
                while self._notifications:
                    n = self._notifications.pop(0)
                    if n.get("method") != "notify_telemetry":
                        continue
                    p, s = n["params"], n["params"]["samples"]
                    for k, t in enumerate(s["board_time_us"]):
                        yield {"board_time_us": t, "setpoint_pa": s["setpoint_pa"][k],
                               "measured_pa": s["measured_pa"][k], "status": s["status_bits"][k],
                               "fault_bitmap": p["fault_bitmap"],
                               "finger_output": s["finger_output"][k]}
                left = end - time.monotonic()
                if left <= 0:
                    return
                try:
                    m = self._conn.messages.get(timeout=min(left, 0.1))
                except queue.Empty:
                    continue
                if m is None:
                    raise _error_class()("unavailable", "palpa serve closed the connection")
                if isinstance(m, dict) and "id" not in m:
                    self._notifications.append(m)
        finally:
            if self._conn is not None:
                self._call("telemetry.unsubscribe", subscription=sub["subscription"])

    def config(self):
        return self._call("board.config.read")

    def apply_config(self, patch):
        self._act("board.config.apply", config=patch)

    def save_config(self):
        self._act("board.config.apply", config={}, save=True)

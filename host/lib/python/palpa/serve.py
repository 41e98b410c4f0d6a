"""A board behind a running `palpa serve` (docs/serve.md): palpa.Device("serve:HOST:PORT") returns
a ServeDevice, which speaks the server's JSON-RPC API over a WebSocket with Python's standard
library only. Several programs watch one board this way while one controls it: reading (info,
diagnostics, configuration, monitor) needs nothing, and the first call that acts on the board
takes control — refused (PalpaError "busy") while another client holds it. Closing gives control
up, and the server then releases the board, as closing a session does.

    with palpa.Device("serve:127.0.0.1:7180") as board:   # "?token=..." beyond loopback
        board.set(0, level=2)
"""
import base64
import hashlib
import json
import math
import numbers
import os
import queue
import socket
import struct
import threading
import time
import urllib.parse

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


_WEBSOCKET_GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"  # RFC 6455, section 1.3
_MAX_MESSAGE_BYTES = 64 << 20  # beyond anything the server sends: more closes the connection


def _check_upgrade(head, key, where):
    """The server's answer to the upgrade, as RFC 6455 (4.1) requires a client to check it: 101,
    Upgrade: websocket, Connection: Upgrade, and the accept key derived from ours (which proves a
    WebSocket server read our request, not a cache or a server of something else)."""
    lines = head.decode("latin-1").split("\r\n")
    status = lines[0]
    parts = status.split(" ", 2)
    if len(parts) < 2 or parts[0] != "HTTP/1.1" or parts[1] != "101":
        raise ConnectionError(f"palpa serve at {where} refused the connection: "
                              f"{status or 'no answer'}")
    fields = {}
    for line in lines[1:]:
        name, sep, value = line.partition(":")
        if sep:
            fields.setdefault(name.strip().lower(), []).append(value.strip())
    upgrade = ",".join(fields.get("upgrade", [])).lower()
    connection = ",".join(fields.get("connection", [])).lower()
    accept = fields.get("sec-websocket-accept", [])
    expected = base64.b64encode(hashlib.sha1((key + _WEBSOCKET_GUID).encode()).digest()).decode()
    if "websocket" not in (t.strip() for t in upgrade.split(",")):
        wrong = "no Upgrade: websocket header"
    elif "upgrade" not in (t.strip() for t in connection.split(",")):
        wrong = "no Connection: Upgrade header"
    elif accept != [expected]:
        wrong = (f"Sec-WebSocket-Accept is {accept[0]!r}, not {expected!r}" if accept
                 else "no Sec-WebSocket-Accept header")
    else:
        return
    raise ConnectionError(f"{where} did not answer as a WebSocket server (is palpa serve listening "
                          f"there?): {status} with {wrong}")


class _Connection:
    """One WebSocket: the handshake checked, masked frames out, frames in on a thread of its own
    that answers the server's pings (three unanswered and the server counts the client gone)."""

    def __init__(self, host, port, token, timeout=10):
        self.sock = socket.create_connection((host, port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        authority = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
        target = "/websocket" + (f"?token={urllib.parse.quote(token)}" if token else "")
        self.sock.sendall((f"GET {target} HTTP/1.1\r\nHost: {authority}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head and len(head) < 16384:
            chunk = self.sock.recv(1)  # a byte at a time: what follows the head is frames
            if not chunk:
                break
            head += chunk
        try:
            _check_upgrade(head, key, authority)
        except ConnectionError:
            self.sock.close()
            raise
        self.sock.settimeout(None)
        self.lock = threading.Lock()
        self.messages = queue.Queue()  # parsed JSON, or None once closed
        threading.Thread(target=self._read, daemon=True).start()

    def _recv(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise EOFError
            data += chunk
        return data

    def send(self, opcode, payload):
        mask = os.urandom(4)
        n = len(payload)
        header = bytes([0x80 | opcode])
        if n < 126:
            header += bytes([0x80 | n])
        elif n < 65536:
            header += bytes([0x80 | 126]) + struct.pack(">H", n)
        else:
            header += bytes([0x80 | 127]) + struct.pack(">Q", n)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        with self.lock:
            self.sock.sendall(header + mask + masked)

    def _read(self):
        message = b""
        try:
            while True:
                b0, b1 = self._recv(2)
                if b1 & 0x80 or b0 & 0x70:
                    break  # a server's frames are unmasked and use no extension (RFC 6455 5.1)
                n = b1 & 0x7F
                if n == 126:
                    n = struct.unpack(">H", self._recv(2))[0]
                elif n == 127:
                    n = struct.unpack(">Q", self._recv(8))[0]
                if n + len(message) > _MAX_MESSAGE_BYTES:
                    break
                payload = self._recv(n)
                opcode = b0 & 0x0F
                if opcode == 0x9:
                    self.send(0xA, payload)
                elif opcode == 0x8:
                    break
                elif opcode in (0x0, 0x1):  # a text message, perhaps in fragments
                    message += payload
                    if b0 & 0x80:
                        self.messages.put(json.loads(message))
                        message = b""
        except (EOFError, OSError, ValueError):
            pass
        self.messages.put(None)

    def close(self):
        try:
            self.send(0x8, struct.pack(">H", 1000))
        except OSError:
            pass
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()


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

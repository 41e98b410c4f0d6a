"""The WebSocket client under ServeDevice (RFC 6455, Python's standard library only): the upgrade
checked as a client must check it, masked frames out, frames in on a thread of its own."""
import base64
import hashlib
import json
import os
import queue
import socket
import struct
import threading
import urllib.parse

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

"""Raw HTTP and WebSocket requests for the serve tests, written by hand for headers a WebSocket
library will not send wrong and for a client that stops answering pings."""
import json
import os
import socket
import struct
import threading
import time


def read_head(sock, step=65536):
    """Bytes up to an HTTP head's blank line and beyond it what came with it (none when step is 1:
    a WebSocket's frames follow), or what came before the connection closed."""
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(step)
        if not chunk:
            break
        data += chunk
    return data


def http(port, request_lines, body=b""):
    """One raw HTTP request; (status, headers, body)."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(("\r\n".join(request_lines) + "\r\n\r\n").encode() + body)
        head, _, rest = read_head(s).partition(b"\r\n\r\n")
        lines = head.decode("latin-1").split("\r\n")
        status = int(lines[0].split()[1]) if lines and len(lines[0].split()) > 1 else 0
        headers = {}
        for line in lines[1:]:
            key, _, value = line.partition(":")
            headers[key.strip().lower()] = value.strip()
        return status, headers, rest


def upgrade_lines(host, origin=None, target="/websocket", extra=()):
    lines = [f"GET {target} HTTP/1.1", f"Host: {host}", "Upgrade: websocket",
             "Connection: Upgrade", "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==",
             "Sec-WebSocket-Version: 13"]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    return lines + list(extra)


class RawClient:
    """A WebSocket client by hand: it answers the server's pings until silence() — then it neither
    reads nor answers, as a closed laptop lid or a frozen tab would."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.sock.sendall(("\r\n".join(upgrade_lines(f"127.0.0.1:{port}")) + "\r\n\r\n").encode())
        data = read_head(self.sock, step=1)
        if b" 101 " not in data.split(b"\r\n")[0]:
            raise AssertionError(f"upgrade refused: {data!r}")
        self.messages = []
        self.pongs = 0
        self.silent = threading.Event()
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _recv(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise EOFError
            data += chunk
        return data

    def _send(self, opcode, payload):
        mask = os.urandom(4)
        header = bytes([0x80 | opcode])
        if len(payload) < 126:
            header += bytes([0x80 | len(payload)])
        else:
            header += bytes([0x80 | 126]) + struct.pack(">H", len(payload))
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        with self.lock:
            self.sock.sendall(header + mask + masked)

    def _read(self):
        try:
            while not self.silent.is_set():
                b0, b1 = self._recv(2)
                n = b1 & 0x7F
                if n == 126:
                    n = struct.unpack(">H", self._recv(2))[0]
                elif n == 127:
                    n = struct.unpack(">Q", self._recv(8))[0]
                payload = self._recv(n)
                if self.silent.is_set():
                    return
                if b0 & 0x0F == 0x9:
                    self._send(0xA, payload)
                    self.pongs += 1
                elif b0 & 0x0F == 0x1:
                    self.messages.append(json.loads(payload))
        except (EOFError, OSError):
            return

    def call(self, method, **params):
        n = len(self.messages)
        self._send(0x1, json.dumps({"jsonrpc": "2.0", "id": 7, "method": method,
                                    "params": params}).encode())
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            for m in self.messages[n:]:
                if m.get("id") == 7:
                    return m
            time.sleep(0.01)
        raise AssertionError(f"no answer to {method}")

    def silence(self):
        self.silent.set()

#!/usr/bin/python3
"""The serve: clients check the server's answer to the WebSocket upgrade (RFC 6455 4.1): a fake
server answers with a wrong Sec-WebSocket-Accept, a 200, a 101 without the Upgrade header, and
the command line (Boost.Beast's client in the library) and the Python module each refuse it
naming what was wrong and the address. The same fake server's correct answer is accepted by both,
so each refusal is the flaw's doing. Usage: handshake_test.py PALPA PYTHON_PACKAGE_DIR"""
import base64
import hashlib
import json
import socket
import subprocess
import sys
import threading

from harness import fail, read_head

GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"


def accept_for(key):
    return base64.b64encode(hashlib.sha1((key + GUID).encode()).digest()).decode()


# Each answer: (name, function of the client's key -> the head the fake server sends).
ANSWERS = {
    "correct": lambda key: ("HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\n"
                            f"Connection: Upgrade\r\nSec-WebSocket-Accept: {accept_for(key)}\r\n"),
    "wrong accept": lambda key: ("HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\n"
                                 "Connection: Upgrade\r\nSec-WebSocket-Accept: "
                                 f"{accept_for(key + 'x')}\r\n"),
    "200": lambda key: "HTTP/1.1 200 OK\r\nContent-Length: 0\r\n",
    "no Upgrade": lambda key: ("HTTP/1.1 101 Switching Protocols\r\nConnection: Upgrade\r\n"
                               f"Sec-WebSocket-Accept: {accept_for(key)}\r\n"),
}


class FakeServer:
    """Answers every upgrade with the answer named in `self.answer`, then closes the connection
    (so a client that accepted it finds the connection closed at its first call)."""

    def __init__(self):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.answer = "correct"
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            conn, _ = self.listener.accept()
            with conn:
                key = ""
                for line in read_head(conn).decode("latin-1").split("\r\n"):
                    name, _, value = line.partition(":")
                    if name.strip().lower() == "sec-websocket-key":
                        key = value.strip()
                conn.sendall((ANSWERS[self.answer](key) + "\r\n").encode())
                try:
                    conn.shutdown(socket.SHUT_WR)
                    conn.recv(4096)  # until the client is done with it
                except OSError:
                    pass


def command_line(palpa, server, answer, words):
    server.answer = answer
    address = f"127.0.0.1:{server.port}"
    r = subprocess.run([palpa, "--device", f"serve:{address}", "--json", "info"],
                       capture_output=True, text=True, timeout=30)
    try:
        message = json.loads(r.stdout)["error"]["message"]
    except (ValueError, KeyError):
        fail(f"palpa info against the {answer} answer: {r.returncode} {r.stdout} {r.stderr}")
    if r.returncode != 3 or address not in message or any(w not in message for w in words):
        fail(f"palpa info against the {answer} answer: {r.returncode} {message!r} (wanted {words})")
    print(f"ok  command line, {answer}: {message}")


def python_module(palpa_module, server, answer, words):
    server.answer = answer
    address = f"127.0.0.1:{server.port}"
    try:
        palpa_module.Device(f"serve:{address}")
    except ConnectionError as e:
        if address not in str(e) or any(w not in str(e) for w in words):
            fail(f"Python against the {answer} answer: {e!r} (wanted {words})")
        print(f"ok  Python, {answer}: {e}")
        return
    except palpa_module.PalpaError as e:
        fail(f"Python against the {answer} answer got past the upgrade: {e}")
    fail(f"Python against the {answer} answer connected")


def main():
    palpa, package_dir = sys.argv[1], sys.argv[2]
    sys.path.insert(0, package_dir)
    import palpa as palpa_module
    server = FakeServer()
    # The correct answer passes the upgrade; the fake server then closes, which the first call
    # (board.info) reports, naming the address: proof that the refusals below are about the
    # answers alone.
    server.answer = "correct"
    r = subprocess.run([palpa, "--device", f"serve:127.0.0.1:{server.port}", "--json", "info"],
                       capture_output=True, text=True, timeout=30)
    if f'"message":"serve:127.0.0.1:{server.port}: board.info: palpa serve' not in r.stdout:
        fail(f"palpa info against a correct upgrade did not pass it: {r.returncode} {r.stdout}")
    try:
        palpa_module.Device(f"serve:127.0.0.1:{server.port}")
        fail("Python connected to a server that closes at once")
    except palpa_module.PalpaError as e:
        if "board.info: palpa serve" not in str(e):
            fail(f"Python against a correct upgrade did not pass it: {e}")
    print("ok  a correct upgrade passes both clients (the fake server then closes)")
    for answer, cli_words, python_words in (
            ("wrong accept", ["Sec-WebSocket-Accept"], ["Sec-WebSocket-Accept"]),
            ("200", ["refused", "200 OK"], ["refused", "200 OK"]),
            ("no Upgrade", ["Upgrade field is missing"], ["no Upgrade: websocket header"])):
        command_line(palpa, server, answer, cli_words)
        python_module(palpa_module, server, answer, python_words)
    print("handshake_test: both serve: clients refuse an upgrade answered wrongly")


if __name__ == "__main__":
    main()

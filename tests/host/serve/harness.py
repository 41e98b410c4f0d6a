"""What the serve tests share: palpa-sim with its truth channel, `palpa serve` in front of it, raw
HTTP and WebSocket requests (raw_requests.py), a JSON-RPC client over python3-websockets, a study
session's files as written, and Debian's chromium for the browser tests."""
import asyncio
import json
import os
import re
import socket
import subprocess
import tempfile
import threading
import time

import websockets

# Raw requests live in their own module; the tests import them from here, as everything they share.
from raw_requests import RawClient, http, read_head, upgrade_lines  # noqa: F401


def fail(message):
    raise AssertionError(message)


class Sim:
    """palpa-sim on a free port, its truth channel read on a thread of its own."""

    def __init__(self, palpa_sim, config="thesis-5finger"):
        self.proc = subprocess.Popen(
            [palpa_sim, "--config", config, "--listen", "tcp:127.0.0.1:0",
             "--truth", "tcp:127.0.0.1:0", "--truth-every-ms", "5"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.address = self.truth_address = None
        while self.address is None or self.truth_address is None:
            line = self.proc.stdout.readline()
            if not line:
                fail("palpa-sim ended before it listened")
            if m := re.search(r"listening on (tcp:\S+)", line):
                self.address = m.group(1)
            if m := re.search(r"truth on tcp:([\d.]+):(\d+)", line):
                self.truth_address = (m.group(1), int(m.group(2)))
        self.samples = []
        self.lock = threading.Lock()
        self.sock = socket.create_connection(self.truth_address)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        buffer = b""
        while True:
            data = self.sock.recv(65536)
            if not data:
                return
            buffer += data
            *lines, buffer = buffer.split(b"\n")
            with self.lock:
                self.samples.extend(json.loads(line) for line in lines if line)

    def latest(self):
        """The newest truth sample (board time, board facts, lines, fingers)."""
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            with self.lock:
                if self.samples:
                    return self.samples[-1]
            time.sleep(0.01)
        fail("no truth from palpa-sim")

    def wait(self, predicate, what, seconds=10):
        """The first truth sample that meets `predicate` within `seconds` of board time."""
        start = self.latest()["board_time_us"]
        while (sample := self._meets(predicate, what, seconds, start)) is None:
            time.sleep(0.02)
        return sample

    async def wait_async(self, predicate, what, seconds=10):
        """wait() for a test that runs an event loop: it yields to it while it waits."""
        start = self.latest()["board_time_us"]
        while (sample := self._meets(predicate, what, seconds, start)) is None:
            await asyncio.sleep(0.01)
        return sample

    def _meets(self, predicate, what, seconds, start):
        sample = self.latest()
        if predicate(sample):
            return sample
        if sample["board_time_us"] > start + seconds * 1e6:
            fingers = [f.get("deformation_mm", f.get("stiffness_n_per_mm")) for f in sample["fingers"]]
            fail(f"{what}: not within {seconds} s of board time ({sample['board']}, "
                 f"fingers {fingers})")
        return None

    def since(self, board_time_us):
        with self.lock:
            return [s for s in self.samples if s["board_time_us"] >= board_time_us]

    def close(self):
        self.proc.terminate()
        self.proc.wait(10)


class Serve:
    """`palpa serve` on a free port in front of `device`."""

    def __init__(self, palpa, device, listen="127.0.0.1:0", extra=()):
        self.stderr = tempfile.TemporaryFile("w+")  # what the server logs, read by log()
        self.proc = subprocess.Popen([palpa, "serve", "--device", device, "--listen", listen,
                                      *extra],
                                     stdout=subprocess.PIPE, stderr=self.stderr, text=True)
        line = self.proc.stdout.readline()
        m = re.search(r"on http://([^/]+):(\d+)/(\?token=(\w+))?", line)
        if not m:
            fail(f"palpa serve did not say where it listens: {line!r}")
        self.port = int(m.group(2))
        self.token = m.group(4)
        self.authority = f"127.0.0.1:{self.port}"
        self.url = f"ws://{self.authority}/websocket"

    def alive(self):
        return self.proc.poll() is None

    def log(self):
        self.stderr.seek(0)
        return self.stderr.read()

    def close(self):
        self.proc.terminate()
        rc = self.proc.wait(10)
        if rc != 0:
            fail(f"palpa serve exited with {rc}: {self.log()}")


class Client:
    """A JSON-RPC client over python3-websockets: calls answered by id, notifications kept."""

    def __init__(self, ws):
        self.ws = ws
        self.next_id = 1
        self.notifications = []

    @classmethod
    async def connect(cls, url, **kwargs):
        return cls(await websockets.connect(url, max_size=None, **kwargs))

    async def answer(self, id_, timeout=10):
        while True:
            message = json.loads(await asyncio_wait(self.ws.recv(), timeout))
            if isinstance(message, dict) and "method" in message and "id" not in message:
                self.notifications.append(message)
                continue
            if id_ is None or (isinstance(message, dict) and message.get("id") == id_):
                return message

    async def call(self, method, **params):
        id_ = self.next_id
        self.next_id += 1
        await self.ws.send(json.dumps({"jsonrpc": "2.0", "id": id_, "method": method,
                                       "params": params}))
        return await self.answer(id_)

    async def result(self, method, **params):
        answer = await self.call(method, **params)
        if "result" not in answer:
            fail(f"{method} {params}: {answer}")
        return answer["result"]

    async def notification(self, method, timeout=10):
        deadline = time.monotonic() + timeout
        while True:
            for i, n in enumerate(self.notifications):
                if n["method"] == method:
                    return self.notifications.pop(i)
            left = deadline - time.monotonic()
            if left <= 0:
                fail(f"no {method} notification")
            try:
                message = json.loads(await asyncio_wait(self.ws.recv(), left))
            except TimeoutError:
                continue
            if "method" in message:
                self.notifications.append(message)

    async def close(self):
        await self.ws.close()


async def asyncio_wait(awaitable, timeout):
    import asyncio
    try:
        return await asyncio.wait_for(awaitable, timeout)
    except asyncio.TimeoutError:
        raise TimeoutError from None


def settle(sim, seconds=1.0):
    """The truth after `seconds` of board time with nothing sent."""
    start = sim.latest()["board_time_us"]
    while sim.latest()["board_time_us"] < start + seconds * 1e6:
        time.sleep(0.02)
    return sim.latest()


def session_on_disk(directory):
    """A study session's files: session.json and the journal's trials, each line whole (a torn
    line fails the caller's test: json.loads raises)."""
    with open(os.path.join(directory, "trials.jsonl")) as f:
        trials = [json.loads(line) for line in f if line.strip()]
    with open(os.path.join(directory, "session.json")) as f:
        return json.load(f), trials


def chromium(window="1280,1000", performance_log=False):
    """Debian's chromium, headless, through chromium-driver and python3-selenium (imported here:
    only the browser tests need it). performance_log keeps the WebSocket frames it receives."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for arg in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                f"--window-size={window}"]:
        options.add_argument(arg)
    if performance_log:
        options.set_capability("goog:loggingPrefs", {"performance": "ALL", "browser": "ALL"})
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def no_console_errors(driver, whose):
    """The page broke no rule of its own Content-Security-Policy and threw nothing."""
    errors = [e for e in driver.get_log("browser")
              if e["level"] == "SEVERE" and "favicon.ico" not in e["message"]]
    if errors:
        fail(f"the {whose} page logged errors: {errors[:3]}")

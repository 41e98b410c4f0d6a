#!/usr/bin/python3
"""A script beside the page: through a running `palpa serve`, take control, set two fingers in two
units, watch a second of telemetry, give the board back. Usage: serve_client.py [ws://HOST:PORT]"""
import asyncio
import itertools
import json
import sys

import websockets


async def main(url):
    async with websockets.connect(f"{url}/websocket") as ws:
        ids = itertools.count(1)

        async def call(method, **params):
            n = next(ids)
            await ws.send(json.dumps({"jsonrpc": "2.0", "id": n, "method": method, "params": params}))
            while True:
                m = json.loads(await ws.recv())
                if m.get("id") == n:
                    if "error" in m:
                        raise RuntimeError(f"{method}: {m['error']['message']}")
                    return m["result"]

        await call("server.connection.identify", client_name="serve_client.py")
        board = await call("board.info")
        print(f"{board['board']['configuration']}: fingers "
              + ", ".join(f"{f['finger']} {f['kind']} ({f['unit']})" for f in board["fingers"]))
        await call("control.take")
        for a in (await call("board.set", targets=[{"finger": 0, "level": 2},
                                                   {"finger": 3, "value": "0.9N/mm"}]))["applied"]:
            print(f"finger {a['finger']}: target {a['target']} {a['unit']}")
        await call("telemetry.subscribe", updates_per_s=30, sample_rate_hz=100)
        updates = 0
        while updates < 30:  # about a second
            m = json.loads(await ws.recv())
            if m.get("method") == "notify_telemetry":
                updates += 1
                outputs = m["params"]["samples"]["finger_output"][-1]
        print("outputs after a second: " + ", ".join(f"{v:.3f}" for v in outputs))
        await call("control.release")  # the board is released: outputs safe, session kept


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1] if len(sys.argv) > 1 else "ws://127.0.0.1:7180"))

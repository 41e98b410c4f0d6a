#!/usr/bin/python3
"""A simulated board served: `palpa serve --device sim:...` starts palpa-sim with its truth side
channel and sends each finger's true output with the telemetry, beside the estimate through the
curve; a --truth address where nothing listens is refused before anything is served.
Usage: truth_test.py PALPA"""
import asyncio
import subprocess
import sys

from harness import Client, Serve, fail


async def check(serve):
    client = await Client.connect(serve.url)
    await client.result("control.take")
    await client.result("telemetry.subscribe", updates_per_s=30)
    await client.result("board.set", targets=[{"finger": 0, "level": 2}])
    for _ in range(300):  # up to ten seconds of updates
        params = (await client.notification("notify_telemetry"))["params"]
        if "finger_truth" not in params:
            fail(f"no true output in the telemetry of a simulated board: {sorted(params)}")
        truth, estimate = params["finger_truth"][0], params["samples"]["finger_output"][-1][0]
        if truth > 0.5:
            print(f"ok  finger 0 true output {truth} mm (estimate {estimate} mm), board time "
                  f"{params['truth_board_time_us']} us")
            break
    else:
        fail("the true output never showed finger 0 moving")
    if len(params["finger_truth"]) != 5:
        fail(f"not one true output per finger: {params['finger_truth']}")
    await client.close()


def main():
    palpa = sys.argv[1]
    serve = Serve(palpa, "sim:thesis-5finger")
    try:
        asyncio.run(check(serve))
    finally:
        serve.close()
    refused = subprocess.run([palpa, "serve", "--device", "sim:thesis-5finger", "--listen",
                              "127.0.0.1:0", "--truth", "tcp:127.0.0.1:1"],
                             capture_output=True, text=True, timeout=60)
    if refused.returncode != 3 or "truth channel" not in refused.stderr:
        fail(f"an unreachable --truth was not refused: {refused.returncode} {refused.stderr}")
    print(f"ok  {refused.stderr.strip()}")
    print("truth_test: a simulated board's true output goes out with its telemetry")


if __name__ == "__main__":
    main()

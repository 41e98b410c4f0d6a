#!/usr/bin/python3
"""palpa serve under load: a board with 8 lines sending every 1 ms tick, 20 python3-websockets
watchers and one page in headless chromium, each subscribed at 30 updates/s. Prints whether any
telemetry was lost between board and server, each client's updates and samples a second, and the
server's processor time. Usage: serve_bench.py PALPA PALPA_SIM [SECONDS]"""
import asyncio
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "host", "serve"))
from harness import Client, Serve, Sim, fail  # noqa: E402
from browser_test import browser  # noqa: E402

WATCHERS = 20


def cpu_seconds(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


async def watch(url, seconds, out):
    client = await Client.connect(url)
    await client.result("telemetry.subscribe", updates_per_s=30, sample_rate_hz=100)
    updates = samples = 0
    last_t, gaps = None, 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        try:
            message = json.loads(await asyncio.wait_for(client.ws.recv(), 1))
        except asyncio.TimeoutError:
            continue
        if message.get("method") != "notify_telemetry":
            continue
        updates += 1
        for t in message["params"]["samples"]["board_time_us"]:
            if last_t is not None and t - last_t > 10000 * 1.5:
                gaps += 1
            last_t = t
            samples += 1
    out.append((updates / seconds, samples / seconds, gaps))
    await client.close()


async def load(serve, seconds, page):
    out = []
    await asyncio.gather(*(watch(serve.url, seconds, out) for _ in range(WATCHERS)))
    return out


def main():
    palpa, palpa_sim = sys.argv[1], sys.argv[2]
    seconds = float(sys.argv[3]) if len(sys.argv) > 3 else 10
    sim = Sim(palpa_sim, config="full-8")
    serve = Serve(palpa, sim.address)
    driver = browser()
    try:
        driver.get(f"http://{serve.authority}/")
        time.sleep(2)
        driver.execute_script(
            "window.__updates = 0; const seen = ws.onmessage;"
            "ws.onmessage = (e) => { if (e.data.includes('notify_telemetry')) window.__updates++;"
            " seen(e); };")
        cpu0, wall0 = cpu_seconds(serve.proc.pid), time.monotonic()
        sim_cpu0 = cpu_seconds(sim.proc.pid)
        watchers = asyncio.run(load(serve, seconds, driver))
        wall = time.monotonic() - wall0
        cpu = cpu_seconds(serve.proc.pid) - cpu0
        sim_cpu = cpu_seconds(sim.proc.pid) - sim_cpu0
        page_rate = driver.execute_script("return window.__updates") / wall

        async def stats():
            client = await Client.connect(serve.url)
            info = await client.result("server.info")
            await client.close()
            return info["stats"]
        s = asyncio.run(stats())
    finally:
        driver.quit()
        serve.close()
        sim.close()
    rates = [w[0] for w in watchers]
    sample_rates = [w[1] for w in watchers]
    print(f"serve bench: full-8 (8 lines, a sample every 1 ms tick), {WATCHERS} watchers + 1 "
          f"chromium page, {seconds:.0f} s")
    print(f"  board -> server: {s['telemetry_samples']} samples, lost on the link "
          f"{s['telemetry_lost_on_link']}, dropped by the link's subscriber "
          f"{s['telemetry_dropped_by_link_subscriber']}, overtaken in the server "
          f"{s['telemetry_overtaken_in_server']}")
    print(f"  watchers: updates/s min {min(rates):.1f} mean {sum(rates) / len(rates):.1f}; "
          f"samples/s min {min(sample_rates):.1f}; gaps over 15 ms "
          f"{sum(w[2] for w in watchers)}; notifications dropped for slow clients "
          f"{s['telemetry_notifications_dropped']}")
    print(f"  page (chromium): {page_rate:.1f} updates/s")
    print(f"  server processor time: {100 * cpu / wall:.1f} % of one core "
          f"(palpa-sim: {100 * sim_cpu / wall:.1f} %); load average {os.getloadavg()[0]:.1f}")
    lost = s["telemetry_lost_on_link"] + s["telemetry_dropped_by_link_subscriber"] + \
        s["telemetry_overtaken_in_server"]
    if lost or min(rates) < 29 or page_rate < 29:
        fail("telemetry lost, or a client below 30 updates/s")


if __name__ == "__main__":
    main()

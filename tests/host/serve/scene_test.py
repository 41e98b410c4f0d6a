#!/usr/bin/python3
"""Scenes behind `palpa serve`: a page's scene document may not name a file on the server; the
operator's --scene file loads by name; pointer samples are notifications, the newest wins, a
watcher's move nothing; the finger over an inclusion stiffens; and when the controller goes away
the scene stops before the board is released, so no queued sample moves a finger afterwards.
Checked on palpa-sim's truth channel. Usage: scene_test.py PALPA PALPA_SIM SCENE_FILE"""
import asyncio
import json
import sys

from harness import Client, Serve, Sim, fail


def expect_error(answer, code, what):
    if answer.get("error", {}).get("code") != code:
        fail(f"{what}: expected error {code}, got {answer}")
    print(f"ok  {what}: {answer['error']['message']}")


async def settle(sim, seconds):
    """The truth after `seconds` of board time, the clients answering pings meanwhile."""
    start = sim.latest()["board_time_us"]
    while sim.latest()["board_time_us"] < start + seconds * 1e6:
        await asyncio.sleep(0.02)
    return sim.latest()


def deformation(sample, finger):
    return sample["fingers"][finger]["deformation_mm"]


async def pointer(client, x, y, force=1.0):
    await client.ws.send(json.dumps({"jsonrpc": "2.0", "method": "scene.pointer",
                                     "params": {"x_mm": x, "y_mm": y, "force_n": force}}))


async def scenes(serve, sim, scene_file):
    a = await Client.connect(serve.url)
    w = await Client.connect(serve.url)
    info = await w.result("scene.info")
    if info["presets"] != ["thesis-three-cube"] or info["loaded"]:
        fail(f"scene.info before any load: {info}")
    expect_error(await w.call("scene.load", name=info["server_scenes"][0]), -32001,
                 "a watcher's scene.load")
    await a.result("control.take")
    doc = json.load(open(scene_file))
    for tissue in ({"file": "/etc/passwd"},
                   {"image": {"path": "/etc/hostname", "mm_per_pixel": 1, "unit": "kPa",
                              "value_at_black": 1, "value_at_white": 2}}):
        expect_error(await a.call("scene.load", scene={**doc, "tissue": tissue}), -32602,
                     f"a scene document naming a file ({list(tissue)[0]})")
    expect_error(await a.call("scene.load", scene={**doc, "fingers": [0, 1, 9]}), -32602,
                 "a scene naming board finger 9")
    expect_error(await a.call("scene.load", name="no such scene"), -32602, "an unknown name")
    expect_error(await a.call("scene.start"), -32602, "scene.start with nothing loaded")
    loaded = await a.result("scene.load", name=info["server_scenes"][0])
    tissue = loaded["tissue"]
    if tissue["extent_mm"] != [120, 30] or len(tissue["values"]) != 61:
        fail(f"the map a page draws: {tissue['extent_mm']}, {len(tissue['values'])} rows")
    print(f"ok  the operator's scene loaded by name: {loaded['name']}, "
          f"{len(tissue['values'][0])} × {len(tissue['values'])} points sent")
    expect_error(await a.call("scene.pointer", x_mm=45, y_mm=15, force_n=1), -32602,
                 "a sample before scene.start")
    await a.result("scene.start")
    for bad in ({"x_mm": 45, "y_mm": 15}, {"x_mm": 45, "y_mm": 15, "force_n": 101},
                {"x_mm": "45", "y_mm": 15, "force_n": 1}, {"x_mm": 1e300, "y_mm": 0, "force_n": 1}):
        expect_error(await a.call("scene.pointer", **bad), -32602, f"scene.pointer {bad}")
    # A watcher's samples move nothing.
    for x in range(40, 62):
        await pointer(w, x, 15)
    quiet = await settle(sim, 0.5)
    if any(deformation(quiet, f) > 0.2 for f in range(3)):
        fail(f"a watcher's samples moved a finger: {quiet['fingers'][:3]}")
    print("ok  a watcher's pointer samples moved no finger")
    # A burst of samples ends at x = 45 mm: finger 1 (15 mm to the right) over cube B.
    for k in range(200):
        await pointer(a, 5 + 40 * k / 199, 15)
    at45 = await sim.wait_async(lambda s: deformation(s, 1) > deformation(s, 0) + 0.3,
                                "finger 1 over cube B")
    state = await a.notification("notify_scene")
    while abs(state["params"].get("input", {}).get("x_mm", 0) - 45) > 1e-6:
        state = await a.notification("notify_scene")
    p = state["params"]
    if p["samples_fed"] + p["samples_overtaken"] != 200 or p["samples_fed"] > 200:
        fail(f"samples fed and overtaken do not add up to the 200 sent: {p}")
    print(f"ok  200 samples: {p['samples_fed']} fed, {p['samples_overtaken']} overtaken by newer; "
          f"finger 1 {deformation(at45, 1):.2f} mm over cube B, finger 0 "
          f"{deformation(at45, 0):.2f} mm beside it")
    if not p["fingers"][1]["touching"] or p["fingers"][1]["target"] <= p["fingers"][0]["target"]:
        fail(f"notify_scene does not show finger 1 the stiffer: {p['fingers']}")
    await pointer(a, 60, 15)
    await sim.wait_async(lambda s: deformation(s, 0) > deformation(s, 1) + 0.3,
                         "finger 0 over cube B")
    print("ok  at x = 60 mm finger 0 is over cube B and the stiffer")
    # The controller goes, a burst of samples behind it: the scene stops, the board is released,
    # and nothing queued re-actuates it.
    for k in range(50):
        await pointer(a, 60 + k / 10, 15)
    await a.close()
    released = await sim.wait_async(lambda s: s["board"]["safe"], "the release")
    after = await settle(sim, 0.5)
    if not after["board"]["safe"] or any(deformation(after, f) > 0.2 for f in range(3)):
        fail(f"a finger moved after the controller left: {after['board']} {after['fingers'][:3]}")
    state = await w.notification("notify_scene")
    while state["params"]["running"]:
        state = await w.notification("notify_scene")
    print(f"ok  the controller left mid-burst: scene stopped, board released "
          f"(faults {released['board']['faults']}), no finger moved in the next 0.5 s")
    b = await Client.connect(serve.url)
    await b.result("control.take")
    expect_error(await b.call("scene.pointer", x_mm=60, y_mm=15, force_n=1), -32602,
                 "a new controller's sample before it starts the scene again")
    await b.close()
    await w.close()


def main():
    palpa, palpa_sim, scene_file = sys.argv[1], sys.argv[2], sys.argv[3]
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address, extra=["--scene", scene_file])
    try:
        asyncio.run(scenes(serve, sim, scene_file))
        if not serve.alive():
            fail("the server died")
    finally:
        serve.close()
        sim.close()
    print("scene_test: scenes loaded, fed latest-wins and stopped with control")


if __name__ == "__main__":
    main()

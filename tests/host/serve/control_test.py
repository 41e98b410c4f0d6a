#!/usr/bin/python3
"""Who controls the board behind `palpa serve`: one controller, watchers refused, control passed by
a deliberate take (the board released first), and a controller that stops answering the server's
pings released after three of them — the board safe, no fault, the server's session kept, and
nothing restored when that client comes back. Checked on palpa-sim's truth channel.
Usage: control_test.py PALPA PALPA_SIM"""
import asyncio
import sys

from harness import Client, RawClient, Serve, Sim, fail, settle

PING_MS, GONE_AFTER = 100, 3


def expect_error(answer, code, what):
    if answer.get("error", {}).get("code") != code:
        fail(f"{what}: expected error {code}, got {answer}")
    print(f"ok  {what}: {answer['error']['message']}")


def actuated(sample):
    return not sample["board"]["safe"]


async def passing(serve, sim):
    a = await Client.connect(serve.url)
    b = await Client.connect(serve.url)
    await a.result("server.connection.identify", client_name="page A")
    expect_error(await b.call("board.set", targets=[{"finger": 0, "level": 2}]), -32001,
                 "a watcher's set, nobody in control")
    await a.result("control.take")
    await a.notification("notify_control")  # everyone hears who controls, the taker too
    await b.notification("notify_control")
    expect_error(await b.call("board.set", targets=[{"finger": 0, "level": 2}]), -32001,
                 "a watcher's set while A controls")
    expect_error(await b.call("board.lines.set", setpoints=[{"line": 0, "kpa": 20}]), -32001,
                 "a watcher's raw line while A controls")
    expect_error(await b.call("board.release"), -32001, "a watcher's release")
    expect_error(await b.call("control.take"), -32002, "a take without force while A controls")
    await a.result("board.set", targets=[{"finger": 0, "level": 2}])
    moved = await sim.wait_async(lambda s: s["fingers"][0]["deformation_mm"] > 0.5,
                                 "A's level 2 on finger 0")
    print(f"ok  A moved finger 0 to {moved['fingers'][0]['deformation_mm']} mm")
    info = await b.result("board.info")  # watchers read
    if info["fingers"][0]["finger"] != 0:
        fail("board.info does not number from 0")
    taken = await b.result("control.take", force=True)
    if not taken["board_released"]:
        fail("control passed without releasing the board first")
    notice = await a.notification("notify_control")
    if notice["params"]["controller"] == 1 or not notice["params"]["board_released"]:
        fail(f"A was not told it lost control: {notice}")
    safe = await sim.wait_async(lambda s: not actuated(s), "the release on passing control")
    print(f"ok  control passed to B by force: board safe at {safe['board_time_us']} us, "
          f"faults {safe['board']['faults']}")
    if safe["board"]["faults"] != 0:
        fail("passing control latched a fault")
    expect_error(await a.call("board.set", targets=[{"finger": 0, "level": 2}]), -32001,
                 "A's set after losing control")
    await b.result("board.set", targets=[{"finger": 1, "level": 1}])
    await sim.wait_async(actuated, "B's set")
    # A watcher may always stop the board.
    await a.result("board.estop")
    stopped = await sim.wait_async(lambda s: s["board"]["faults"] != 0 and not actuated(s),
                                   "a watcher's E-stop")
    print(f"ok  a watcher's E-stop: faults {stopped['board']['faults']}")
    await b.result("board.clear")
    await b.result("control.release")
    await a.close()
    await b.close()


async def missed_pings(serve, sim):
    watcher = await Client.connect(serve.url)
    page = await asyncio.to_thread(RawClient, serve.port)
    taken = await asyncio.to_thread(page.call, "control.take")
    if "result" not in taken:
        fail(f"the page could not take control: {taken}")
    await watcher.notification("notify_control")
    answer = await asyncio.to_thread(page.call, "board.set", targets=[{"finger": 0, "level": 2}])
    if "result" not in answer:
        fail(f"the page's set: {answer}")
    await sim.wait_async(actuated, "the page's set")
    # Quiet but alive: it sends nothing for a second and answers every ping, and keeps control.
    quiet_from = sim.latest()["board_time_us"]
    await asyncio.to_thread(settle, sim, 1.0)
    if any(not actuated(s) for s in sim.since(quiet_from)):
        fail("a quiet client that answers pings lost the board")
    if page.pongs < 5:
        fail(f"the server pinged only {page.pongs} times in a second")
    print(f"ok  a quiet page answering pings kept control ({page.pongs} pongs so far)")
    # Then it goes silent: neither reading nor answering.
    page.silence()
    silent_at = sim.latest()["board_time_us"]
    released = await sim.wait_async(lambda s: not actuated(s), "the release after missed pings")
    notice = await watcher.notification("notify_control")
    waited_ms = (released["board_time_us"] - silent_at) / 1000
    print(f"ok  silent page released after {waited_ms:.0f} ms of board time: {notice['params']['reason']}")
    if "pings unanswered" not in notice["params"]["reason"] or notice["params"]["controller"] is not None:
        fail(f"the release does not say why: {notice}")
    # Three pings must have gone unanswered: never before two whole intervals have passed.
    if waited_ms < (GONE_AFTER - 1) * PING_MS:
        fail(f"released after {waited_ms} ms: before {GONE_AFTER} pings could be missed")
    if waited_ms > 2000:
        fail(f"released only after {waited_ms} ms of board time")
    if released["board"]["faults"] != 0:
        fail(f"the release latched a fault: {released['board']}")
    # The server kept its session: a new controller moves the board at once, no reopening.
    back = await Client.connect(serve.url)
    info = await back.result("server.info")
    if info["controls"] or info["controller"] is not None:
        fail("a reconnecting page got control back without asking")
    await asyncio.to_thread(settle, sim, 0.3)
    if actuated(sim.latest()):
        fail("reconnecting re-actuated the board")
    print("ok  reconnecting restored nothing")
    await back.result("control.take")
    await back.result("board.set", targets=[{"finger": 2, "level": 1}])
    await sim.wait_async(actuated, "the next controller's set")
    stats = (await back.result("server.info"))["stats"]
    if stats["telemetry_lost_on_link"] != 0:
        fail(f"telemetry lost on the link: {stats}")
    await back.close()
    await watcher.close()


def main():
    palpa, palpa_sim = sys.argv[1], sys.argv[2]
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address)
    try:
        asyncio.run(passing(serve, sim))
        asyncio.run(missed_pings(serve, sim))
    finally:
        serve.close()
        sim.close()
    print("control_test: one controller, passed by a user's take, released when it goes away")


if __name__ == "__main__":
    main()

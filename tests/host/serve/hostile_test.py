#!/usr/bin/python3
"""10 000 malformed and hostile messages from the controlling client of `palpa serve`: each gets a
JSON-RPC error (or, for a notification, nothing), the server stays up, and the fingers stay where
they were — read on palpa-sim's truth channel, which nothing in the protocol can fake.
Usage: hostile_test.py PALPA PALPA_SIM [COUNT]"""
import asyncio
import json
import random
import sys

from harness import Client, Serve, Sim, fail, settle

METHODS = ["server.info", "server.connection.identify", "control.take", "control.release",
           "telemetry.subscribe", "telemetry.unsubscribe", "board.info", "board.diagnostics",
           "board.config.read", "board.config.apply", "board.set", "board.lines.set",
           "board.estop", "board.clear", "board.release"]
BAD_NUMBERS = [-1, 5, 256, 1.5, 2**64, -2**63 - 1, 1e300, -1e300, True, None, "0", [], {}, "L2"]
BAD_VALUES = ["10kpa", "L-1", "inf", "nan", "0x1", "1.5", "", "1.2MM", "L", "0.9 N/mm",
              "9" * 80, "-10kPa-", "L2.5", "\u0000", "1e999mm"]


def bad_target(rng):
    """One target no finger can take: a wrong finger, a wrong type, or a value out of range."""
    good_finger = rng.randrange(5)
    choices = [
        lambda: {"finger": rng.choice(BAD_NUMBERS), "level": 1},
        lambda: {"finger": good_finger},
        lambda: {"finger": good_finger, "level": 1, "mm": 1},
        lambda: {"finger": good_finger, "level": rng.choice([-1, 1.5, "2", 1e9, None, True])},
        lambda: {"finger": good_finger, "value": rng.choice(BAD_VALUES)},
        lambda: {"finger": good_finger, "value": rng.choice([1, None, [], {}])},
        lambda: {"finger": 0, "mm": rng.choice([99, -5, 1e9, "1", None])},
        lambda: {"finger": 3, "n_per_mm": rng.choice([5, -1, 0.1, 1e308])},
        lambda: {"finger": 0, "n_per_mm": 1.0},  # N/mm means nothing for a pneumatic finger
        lambda: {"finger": 3, "mm": 1.0},        # mm means nothing for a jamming finger
        lambda: {"finger": good_finger, "kpa": rng.choice([1e9, -1e9, 500, "30"])},
        lambda: {"finger": good_finger, "level": 1, "extra": 1},
        lambda: rng.choice([1, "x", None, []]),
    ]
    return rng.choice(choices)()


def bad_params(rng, method):
    """Parameters `method` refuses (never valid ones: nothing here may move the board)."""
    if method == "board.set":
        targets = [bad_target(rng) for _ in range(rng.randint(1, 3))]
        return rng.choice([{"targets": targets},
                           {"targets": targets + [{"finger": 1, "level": 1}]},  # one bad spoils all
                           {"targets": []}, {"targets": "L2"}, {"targets": [{"finger": 1, "level": 1}] * 2},
                           {"targets": [{"finger": i, "level": 1} for i in range(6)]}, {}])
    if method == "board.lines.set":
        return rng.choice([{"setpoints": [{"line": rng.choice(BAD_NUMBERS), "kpa": 10}]},
                           {"setpoints": [{"line": 0, "kpa": rng.choice([1e9, -1e9, "3", None, 150])}]},
                           {"setpoints": [{"line": 0}]}, {"setpoints": [{"line": 0, "kpa": 1}] * 2},
                           {"setpoints": {}}, {"lines": []}])
    if method == "board.config.apply":
        return rng.choice([{"config": rng.choice([1, "x", [], None])},
                           {"config": {"board": {"host_timeout_us": rng.choice([-1, "x", 1e20, None])}}},
                           {"config": {"lines": [{"line": 0, "limit_max_pa": rng.choice([1e12, "x", -1e12])}]}},
                           {"config": {"fingers": [{"finger": 9}]}},
                           {"config": {"numbering": "from 1"}},
                           {"config": {}, "save": "yes"}, {}])
    if method.startswith("telemetry."):
        return rng.choice([{"updates_per_s": rng.choice([0, 1e6, "30", None, -1])},
                           {"sample_rate_hz": rng.choice([0, 1e9, True])},
                           {"subscription": rng.choice([0, -1, "1", 2**70])}, {"x": 1}])
    if method == "control.take":
        return rng.choice([{"force": rng.choice(["yes", 1, None, []])}, {"x": 1}])
    if method == "server.connection.identify":
        return rng.choice([{"client_name": rng.choice(["", 1, None, "x" * 65])}, {"x": 1}])
    return {rng.choice(["x", "force", "finger", "__proto__", ""]): rng.choice([1, "x", None, {}])}


def hostile(rng, i):
    """(text, answered): one hostile message, and whether an error must come back for it."""
    kind = rng.randrange(14)
    if kind == 0:  # bytes that are not JSON
        n = rng.randint(0, 200)
        return "".join(chr(rng.randint(1, 0x2FF)) for _ in range(n)), True
    if kind == 1:  # valid JSON cut short
        text = json.dumps({"jsonrpc": "2.0", "id": i, "method": "board.set",
                           "params": {"targets": [{"finger": 0, "level": 2}]}})
        return text[:rng.randint(1, len(text) - 1)], True
    if kind == 2:  # JSON that is not a request object
        return json.dumps(rng.choice([1, "x", None, True, [1, 2], 1e308])), True
    if kind == 3:  # an envelope wrong in one member
        message = {"jsonrpc": "2.0", "id": i, "method": "board.info"}
        member = rng.choice(["jsonrpc", "method", "id", "params", "extra"])
        message[member] = rng.choice({"jsonrpc": [None, 2, "2", "1.0", 2.0, {}],
                                      "method": [None, 1.5, {}, [], 2, True],
                                      "id": [1.5, {}, [], True, False],
                                      "params": [None, 1.5, [], [1], "x", 2, True],
                                      "extra": [None, 1, "x"]}[member])
        return json.dumps(message), True
    if kind == 4:  # methods that do not exist
        name = rng.choice(["board", "board.", "board.set.x", "Board.set", "__proto__", "x" * 1000,
                           "board.estop ", "server.shutdown", "scene.load", "", "rpc.discover"])
        return json.dumps({"jsonrpc": "2.0", "id": i, "method": name}), True
    if kind == 5:  # batches: empty, too many, of bad entries
        choice = rng.randrange(3)
        if choice == 0:
            return "[]", True
        if choice == 1:
            return json.dumps([{"jsonrpc": "2.0", "id": j, "method": "board.info"} for j in range(65)]), True
        return json.dumps([{"jsonrpc": "2.0", "id": i, "method": "board.set", "params": {}}, 1, "x"]), True
    if kind == 6:  # too large (read and dropped)
        return json.dumps({"jsonrpc": "2.0", "id": i, "method": "board.set",
                           "params": {"pad": "x" * rng.randint(65537, 200000)}}), True
    if kind == 7:  # deeply nested
        depth = rng.randint(100, 20000)
        return "[" * depth + "]" * depth, True
    if kind == 8:  # a notification with bad params: no answer, and nothing done
        method = rng.choice(METHODS)
        return json.dumps({"jsonrpc": "2.0", "method": method, "params": bad_params(rng, method)}), False
    if kind == 9:  # strange ids
        return json.dumps({"jsonrpc": "2.0", "id": rng.choice([{"a": 1}, [1], 1.5]), "method": "board.estop"}), True
    method = rng.choice(METHODS)
    return json.dumps({"jsonrpc": "2.0", "id": i, "method": method, "params": bad_params(rng, method)}), True


async def attack(serve, sim, count):
    client = await Client.connect(serve.url)
    await client.result("control.take")
    # Finger 1 at level 1 and finger 4 stiffened: something to move, if anything could.
    await client.result("board.set", targets=[{"finger": 0, "level": 1}, {"finger": 3, "level": 1}])
    before = await asyncio.to_thread(settle, sim, 2.5)  # the loop keeps answering pings
    rng = random.Random(36)
    errors = binary = 0
    for i in range(count):
        if rng.randrange(200) == 0:  # binary frames carry no JSON-RPC
            await client.ws.send(bytes(rng.randrange(256) for _ in range(rng.randint(0, 64))))
            answered = True
        else:
            text, answered = hostile(rng, i)
            await client.ws.send(text)
        if not answered:
            continue
        answer = await client.answer(None)
        entries = answer if isinstance(answer, list) else [answer]
        for entry in entries:
            if "error" not in entry or "result" in entry:
                fail(f"message {i} was not refused: {entry}")
            errors += 1
    if not serve.alive():
        fail("the server died")
    info = await client.result("server.info")
    if not info["controls"]:
        fail("the attacking client lost control: something was taken as a call")
    after = await asyncio.to_thread(settle, sim, 0.5)
    await client.close()
    return before, after, errors, info["stats"]


def main():
    palpa, palpa_sim = sys.argv[1], sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 10000
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address)
    try:
        before, after, errors, stats = asyncio.run(attack(serve, sim, count))
    finally:
        serve.close()
        sim.close()
    print(f"{count} hostile messages, {errors} errors answered; server stats {stats}")
    if after["board"]["faults"] != 0 or after["board"]["safe"]:
        fail(f"the board was stopped or faulted: {after['board']}")
    for f, (b, a) in enumerate(zip(before["fingers"], after["fingers"])):
        for key in b:
            # The plant's own drift over the attack's seconds is microns (creep); a move is not.
            if abs(a[key] - b[key]) > 0.02:
                fail(f"finger {f} moved: {key} {b[key]} -> {a[key]}")
    for l, (b, a) in enumerate(zip(before["lines"], after["lines"])):
        if abs(a["command_pa"] - b["command_pa"]) > 500:
            fail(f"line {l}'s command moved: {b['command_pa']} -> {a['command_pa']}")
    print("hostile_test: the server stayed up and no finger moved "
          f"(finger 0 {before['fingers'][0]} -> {after['fingers'][0]})")


if __name__ == "__main__":
    main()

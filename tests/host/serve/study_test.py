#!/usr/bin/python3
"""A study through `palpa serve`'s API, in front of palpa-sim: the experimenter starts a short
study (two conditions, once each) and a second client, the participant, answers every trial;
the records on disk equal what the API reported, the triggers come with increasing board times,
the participant's channel carries nothing of the condition; bad inputs are refused saying what;
the participant's stop — while a trial's display settles, and while a trial asks — vents every
finger (palpa-sim's truth) and keeps only whole trials, and resuming completes the session; a
missing trigger line refuses palpa serve before the board. Usage: study_test.py PALPA PALPA_SIM"""
import asyncio
import json
import os
import subprocess
import sys
import tempfile
import time

from harness import Client, Serve, Sim, fail, session_on_disk

STUDY = {
    "schema": "palpa-study", "schema_version": 1, "name": "two-web",
    "description": "Two conditions once each, at once: a short study for the API's test.",
    "finger_kind": "pneumatic", "fingers": 3, "unit": "kPa", "cap_kpa": 40,
    "reset": {"hold_ms": 300},
    # Steady for 200 ms before the runner calls a display settled: the window in which the stop
    # while settling must land is at least that wide, whatever the machine's load.
    "settle": {"hold_ms": 200},
    "conditions": [{"values": [0, 30, 0]}, {"values": [10, 10, 10]}],
    "blocks": [{"name": "at-once", "mode": "simultaneous", "repetitions": 1}],
}
# What the participant's channel must never carry: the condition, the stimulus, the scoring.
SECRETS = ["condition", "stimulus", "expected", "correct", "0-30-0", "10-10-10", "kPa", "block"]


async def expect_error(client, method, says, **params):
    answer = await client.call(method, **params)
    if "error" not in answer or says not in answer["error"]["message"]:
        fail(f"{method} {params}: expected an error saying {says!r}, got {answer}")
    return answer["error"]["message"]


async def participant_state(part, state, timeout=20):
    while True:
        n = await part.notification("notify_study_participant", timeout)
        if n["params"]["state"] == state:
            return n["params"]


async def answer_all(part, until_state, answers, stop_after=None, bystander=None):
    """Answers each trial asked (a tumour under finger 2), until `until_state`; with stop_after,
    stops the session once that many trials are answered, while the next is under way. A
    bystander (a client outside the participant's view) tries each answer first: refused."""
    while True:
        n = (await part.notification("notify_study_participant", 30))["params"]
        if n["state"] == until_state:
            return n
        if n["state"] == "break":  # a resumed session starts with a rest: the participant goes on
            await part.result("study.next")
        if n["state"] == "answer":
            if stop_after is not None and len(answers) == stop_after:
                return n
            await expect_error(part, "study.answer", "is not the trial asked",
                               trial=n["trial"] + 1, tumour=True, fingers=[False, True, False])
            await expect_error(part, "study.answer", "finger", trial=n["trial"], tumour=True,
                               fingers=[False, True])
            if bystander is not None:
                await expect_error(bystander, "study.answer", "only from a client in the channel "
                                   "study.participant", trial=n["trial"], tumour=False,
                                   fingers=[False, False, False])
            answers.append(await part.result("study.answer", trial=n["trial"], tumour=True,
                                             fingers=[False, True, False]))


async def answer_one(part, answers):
    """Answers the next trial asked (a tumour under finger 2), and returns at once."""
    n = await participant_state(part, "answer")
    answers.append(await part.result("study.answer", trial=n["trial"], tumour=True,
                                     fingers=[False, True, False]))


def stimulus_frames(sim, since_us):
    """The board times at which a trial's stimulus took effect: a line commanded above 5 kPa in
    the first truth sample after one with every line vented (the reset)."""
    frames, reset = [], False
    for s in sim.since(since_us):
        if all(l["command_pa"] < 500 for l in s["lines"]):
            reset = True
        elif reset and any(l["command_pa"] > 5000 for l in s["lines"]):
            frames.append(s["board_time_us"])
            reset = False
    return frames


async def stopped_and_released(sim, part, sessions, participant, kept, when):
    """After study.stop: every line vented and every finger soft within 3 s (truth), the
    participant told, the session incomplete with `kept` whole trials journalled."""
    vented = await sim.wait_async(
        lambda s: all(abs(l["chamber_pa"]) < 500 for l in s["lines"])
        and all(f["deformation_mm"] < 0.05 for f in s["fingers"]), "every finger vented", 3)
    await participant_state(part, "stopped")
    session, trials = session_on_disk(os.path.join(sessions, "two-web", participant))
    if session["complete"] or len(trials) != kept:
        fail(f"after the stop {when}: complete {session['complete']}, {len(trials)} trials")
    print(f"ok  stopped {when}: every line at "
          f"{max(abs(l['chamber_pa']) for l in vented['lines']):.0f} Pa or less, "
          f"{kept} trial kept whole")


def refused_trigger_line(palpa, tmp):
    """palpa serve --trigger-gpio with a line that is not there: refused before the board is
    reached (the board named is a port where nothing listens, which would exit 3) and before the
    study directory is made; without --study-dir it has nothing to pulse for."""
    sessions = os.path.join(tmp, "never")
    r = subprocess.run([palpa, "serve", "--device", "tcp:127.0.0.1:1", "--study-dir", sessions,
                        "--trigger-gpio", "nochip:0"], capture_output=True, text=True, timeout=20)
    if r.returncode != 1 or "--trigger-gpio 'nochip:0': no GPIO chip 'nochip'" not in r.stderr:
        fail(f"a missing trigger line: exit {r.returncode}, {r.stderr!r}")
    if os.path.exists(sessions):
        fail("a refused palpa serve made its study directory")
    r = subprocess.run([palpa, "serve", "--device", "tcp:127.0.0.1:1", "--trigger-gpio",
                        "nochip:0"], capture_output=True, text=True, timeout=20)
    if r.returncode != 2 or "it needs --study-dir DIR" not in r.stderr:
        fail(f"--trigger-gpio without --study-dir: exit {r.returncode}, {r.stderr!r}")
    print("ok  a missing trigger line refused before the board (exit 1), and one without "
          "--study-dir (exit 2)")


async def experimenter_events(exp):
    """The experimenter's events up to the session's end."""
    events = []
    while not events or events[-1]["event"] != "finished":
        events.append((await exp.notification("notify_study", 30))["params"])
    return events


async def main(palpa, palpa_sim):
    began = time.monotonic()
    tmp = tempfile.mkdtemp(prefix="palpa-study-web-")
    study_file = os.path.join(tmp, "two-web.json")
    with open(study_file, "w") as f:
        json.dump(STUDY, f)
    sessions = os.path.join(tmp, "sessions")
    refused_trigger_line(palpa, tmp)
    sim = Sim(palpa_sim, "thesis-pneumatic-3")
    serve = Serve(palpa, sim.address, extra=["--study-dir", sessions, "--study", study_file])
    exp = await Client.connect(serve.url)
    part = await Client.connect(serve.url)
    try:
        await part.result("study.watch", view="participant")  # first, as its page does
        names = [s["name"] for s in (await part.result("study.list"))["studies"]]
        if not {"thesis-pneumatic", "thesis-jamming", "two-web"} <= set(names):
            fail(f"study.list: {names}")
        await expect_error(exp, "study.start", "take control first", study="two-web",
                           participant="P01")
        await exp.result("control.take")
        await expect_error(exp, "study.start", 'no study "nope"', study="nope", participant="P01")
        await expect_error(exp, "study.start", "names no file", study=study_file, participant="P1")
        await expect_error(exp, "study.start", "cannot name a directory", study="two-web",
                           participant="../P01")
        await expect_error(exp, "study.start", "blocks[0].repetitions", participant="P01",
                           study={**STUDY, "blocks": [{"name": "b", "mode": "simultaneous", "repetitions": 0}]})
        await expect_error(exp, "study.watch", "'view'", view="everything")
        await expect_error(part, "study.answer", "no study session is running", trial=0,
                           tumour=False, fingers=[False, False, False])
        await exp.result("study.watch", view="experimenter")

        # A whole session, answered by the participant's client.
        session_began = sim.latest()["board_time_us"]
        started = await exp.result("study.start", study="two-web", participant="P01")
        if started["out_dir"] != "two-web/P01" or started["provenance"] is None:
            fail(f"study.start: {started}")
        if started["provenance"]["sim"] is not None:  # a tcp: board may be any board
            fail(f"a board reached over tcp: recorded as simulated: {started['provenance']}")
        answers = []
        await answer_all(part, "finished", answers, bystander=exp)
        events = await experimenter_events(exp)
        done = [e for e in events if e["event"] == "finished"]
        if len(done) != 1 or not done[0]["complete"]:
            fail(f"no complete session: {events[-3:]}")
        session, trials = session_on_disk(os.path.join(sessions, "two-web", "P01"))
        reported = [e["record"] for e in events if e["event"] == "trial_answered"]
        for r in reported:
            del r["correct"]
        if not session["complete"] or trials != reported or len(trials) != 2:
            fail(f"records on disk {trials} differ from the API's {reported}")
        if any(t["answer"] != {"tumour": True, "fingers": [False, True, False]} for t in trials):
            fail(f"an answer kept is not the participant's: {trials}")
        triggers = [e for e in events if e["event"] == "trigger"]
        times = [t["board_ms"] for t in triggers]
        if [t["kind"] for t in triggers] != ["settled", "answered"] * 2 or times != sorted(times):
            fail(f"triggers: {triggers}")
        for t, r in zip(triggers[0::2], trials):
            if round(t["board_ms"]) != r["settled_board_ms"]:
                fail(f"the settled trigger {t} is not the record's {r['settled_board_ms']}")
        settle_ms = [round(t["board_ms"] - f / 1000) for t, f in
                     zip(triggers[0::2], stimulus_frames(sim, session_began))]
        print(f"ok  a session through the API: 2 trials, records on disk as reported, triggers "
              f"at board ms {[round(t) for t in times]}")
        await expect_error(exp, "study.start", "already holds", study="two-web", participant="P01")

        # The stop while the display settles — after trial 1's answer and reset, once the next
        # stimulus frame is on the board and before the runner calls it settled: the board
        # released, no half trial journalled, no settle moment of it published.
        await exp.result("study.start", study="two-web", participant="P02")
        answers = []
        await answer_one(part, answers)
        await sim.wait_async(lambda s: all(l["command_pa"] < 500 for l in s["lines"]),
                             "trial 1's reset after its answer")
        frame = await sim.wait_async(lambda s: any(l["command_pa"] > 5000 for l in s["lines"]),
                                     "the next trial's stimulus frame")
        await part.result("study.stop")
        await stopped_and_released(sim, part, sessions, "P02", 1, "while the display settled")
        events = await experimenter_events(exp)
        second = [e for e in events if e["event"] in ("trigger", "trial_started", "trial_answered")
                  and e.get("trial", e.get("record", {}).get("index")) != answers[0]["trial"]]
        if second:
            fail(f"the stopped trial was settled or answered: {second}")
        if "stopped" not in events[-1]["message"] or "--resume continues" not in events[-1]["message"]:
            fail(f"the session's end after the stop: {events[-1]}")
        released = next(t for t in sim.since(frame["board_time_us"])
                        if all(l["command_pa"] < 500 for l in t["lines"]))
        print(f"    released {(released['board_time_us'] - frame['board_time_us']) / 1000:.0f} ms "
              f"after the stimulus frame (undisturbed trials settled {settle_ms} ms after theirs); "
              f"{events[-1]['message']}")

        # Resumed, then stopped in the next trial after its stimulus showed, while it asks.
        await exp.result("study.start", study="two-web", participant="P02", resume=True)
        await participant_state(part, "break")  # a resumed session starts with a rest
        await expect_error(exp, "study.next", "only from a client in the channel study.participant")
        await part.result("study.next")
        asked = await participant_state(part, "answer")
        await sim.wait_async(lambda s: any(l["chamber_pa"] > 5000 for l in s["lines"]),
                             "a stimulus shown before the stop")
        await part.result("study.stop")
        await stopped_and_released(sim, part, sessions, "P02", 1, f"at trial {asked['trial']}, asking")
        await experimenter_events(exp)
        await exp.result("study.start", study="two-web", participant="P02", resume=True)
        await answer_all(part, "finished", answers)
        session, trials = session_on_disk(os.path.join(sessions, "two-web", "P02"))
        if not session["complete"] or sorted(t["index"] for t in trials) != [0, 1]:
            fail(f"the resumed session: {session['complete']}, {trials}")
        print("ok  resumed twice: the session completed, each trial once")

        # Everything the participant's socket got: prompts, never the condition.
        for n in part.notifications:
            text = json.dumps(n)
            if n["method"] != "notify_study_participant" and n["method"] != "notify_control":
                fail(f"the participant got {n['method']}")
            for secret in SECRETS:
                if secret in text:
                    fail(f"the participant's channel carried {secret!r}: {text}")
    finally:
        await exp.close()
        await part.close()
        serve.close()
        sim.close()

    # palpa serve starting palpa-sim itself: the records name the simulated board's seed and unit.
    own = Serve(palpa, "sim:thesis-pneumatic-3",
                extra=["--study-dir", sessions, "--study", study_file])
    client = await Client.connect(own.url)
    try:
        await client.result("control.take")
        started = await client.result("study.start", study="two-web", participant="P03")
        said = started["provenance"]["sim"]
        if not said or not isinstance(said.get("unit"), int) or not isinstance(said.get("seed"), int):
            fail(f"a palpa-sim started by palpa serve, recorded as {started['provenance']}")
        await client.result("study.stop")
        with open(os.path.join(sessions, "two-web", "P03", "session.json")) as f:
            session = json.load(f)  # stopped before a trial was answered: no trials.jsonl yet
        if session["provenance"]["sim"] != said:
            fail(f"session.json's sim {session['provenance']['sim']} is not the API's {said}")
        print(f"ok  a palpa-sim started by palpa serve: unit {said['unit']}, seed {said['seed']}")
    finally:
        await client.close()
        own.close()
    print(f"study_test: a study run, stopped and resumed through the API, "
          f"{time.monotonic() - began:.1f} s")


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1], sys.argv[2]))

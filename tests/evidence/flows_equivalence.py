#!/usr/bin/python3
"""Before/after check for a refactoring of the host's flows: runs a seeded `palpa calibrate --rig
sim --quick` and `palpa demo` with two builds (each a directory holding palpa and palpa-sim) and
compares what they write: the calibration file, raw data and report, the demo's chart, and both
commands' output.

palpa-sim runs in real time, so two runs of one build already differ in their readings (the
host's commands land on other board ticks), and a chart's axes follow its data. The check
therefore runs the first build twice and asks of every file what holds between those two runs:
the calibration file, raw data and command output byte-identical once every number is masked;
the report and chart with the same words in the same order and the same elements drawn (axis
ticks aside, which follow the data). The numbers' largest before/after difference is printed
beside the run-to-run one. The in-process, virtual-time
check that the library session writes byte for byte what the protocol ran is
tests/calibration/session_test.cc.

usage: flows_equivalence.py BEFORE_DIR AFTER_DIR [--seed N] [--work DIR]"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def run(build, args, work, name, attempts=3):
    """palpa's output; a run that stops (a loaded machine can starve palpa-sim's board of its
    host past the host-silence timeout, in either build) is run again, up to `attempts`."""
    env = dict(os.environ, PALPA_SIM=os.path.join(build, "palpa-sim"))
    env.pop("PALPA_SIM_ARGS", None)
    for attempt in range(attempts):
        out = subprocess.run([os.path.join(build, "palpa")] + args, env=env, cwd=work,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if out.returncode == 0:
            return out.stdout
        last = out.stderr.replace("\r", "\n").strip().splitlines()[-2:]
        print(f"{name}: palpa {args[0]} exited {out.returncode} ({' '.join(last)})"
              f"{'; again' if attempt + 1 < attempts else ''}", file=sys.stderr)
        for f in args:  # a stopped calibration leaves its directory: start afresh
            if f.startswith(work) and os.path.isdir(f):
                shutil.rmtree(f)
    sys.exit(f"{name}: palpa {' '.join(args)} failed {attempts} times")


def outputs(build, work, seed, name):
    """{file name: text} of one build's calibration and demo."""
    os.makedirs(work)
    cal = os.path.join(work, "cal")
    # Half the default speed: the board's host-silence timeout is then 50 ms of real time, room
    # for a machine loaded with other work.
    texts = {"calibrate.out": run(build, ["calibrate", "--rig", "sim", "--finger", "1", "--quick",
                                          "--seed", str(seed), "--speed", "2", "--out", cal],
                                  work, name)}
    texts["demo.out"] = run(build, ["demo", "--speed", "2", "--out", os.path.join(work, "demo.svg")],
                            work, name)
    for name in ("calibrate.out", "demo.out"):
        with open(os.path.join(work, name), "w") as fh:
            fh.write(texts[name])
    for f in sorted(os.listdir(cal)):
        with open(os.path.join(cal, f)) as fh:
            texts["cal/" + f] = fh.read()
    with open(os.path.join(work, "demo.svg")) as fh:
        texts["demo.svg"] = fh.read()
    # Paths name the run's directory: the same in every run once it is named WORK.
    return {k: v.replace(work, "WORK") for k, v in texts.items()}


WORDS = re.compile(r"[A-Za-z][A-Za-z_%()/-]*")
DRAWN = re.compile(r"<(polyline|path|rect|circle|polygon)\b")


def shape(name, text):
    """What must not change between runs of one build: masked text, or for a chart (SVG, the
    report's HTML) its words and the elements it draws, axis ticks aside."""
    if name.endswith((".svg", ".html")):
        drawn = {}
        for tag in DRAWN.findall(text):
            drawn[tag] = drawn.get(tag, 0) + 1
        return (WORDS.findall(re.sub(r"<[^>]*>", " ", text)), sorted(drawn.items()))
    return NUMBER.sub("N", text)


def numbers(text):
    return [float(x) for x in NUMBER.findall(text)]


def spread(a, b):
    """The largest difference between matching numbers, relative to the larger's size."""
    worst = 0.0
    for x, y in zip(numbers(a), numbers(b)):
        if x != y:
            worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-9))
    return worst


def main():
    p = argparse.ArgumentParser()
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--work", default=None)
    a = p.parse_args()
    work = a.work or tempfile.mkdtemp(prefix="palpa-flows-")
    runs = {name: outputs(build, os.path.join(work, name), a.seed, name)
            for name, build in (("before", a.before), ("before-again", a.before),
                                ("after", a.after))}
    ok = True
    for name in sorted(runs["before"]):
        shapes = {r: shape(name, runs[r].get(name, "<missing>")) for r in runs}
        control_holds = shapes["before"] == shapes["before-again"]
        same_shape = shapes["before"] == shapes["after"]
        control = spread(runs["before"][name], runs["before-again"][name])
        change = spread(runs["before"][name], runs["after"].get(name, ""))
        identical = runs["before"][name] == runs["after"].get(name)
        print(f"{name:16} {'same' if same_shape else 'DIFFERENT'}"
              f"{'' if control_holds else ' (and between runs of one build: the check is void)'};"
              f" {'byte-identical' if identical else 'numbers differ'}: before/after up to"
              f" {100 * change:.3g} %, before/before up to {100 * control:.3g} %")
        ok = ok and same_shape and control_holds
    if sorted(runs["before"]) != sorted(runs["after"]):
        print("files differ:", sorted(runs["before"]), sorted(runs["after"]))
        ok = False
    print("equivalent" if ok else "NOT equivalent", f"(runs in {work})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

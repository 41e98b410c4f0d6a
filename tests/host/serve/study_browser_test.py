#!/usr/bin/python3
"""The two study views in real browsers (headless chromium, python3-selenium) against
`palpa serve` and palpa-sim: the experimenter's page starts a three-trial study, the
participant's page (a browser of its own) is clicked through two trials and its stop button
pressed during the third — every finger vents (palpa-sim's truth), the journal keeps the two
trials, the experimenter's table fills as they are answered. Everything the participant's page
showed, and every WebSocket frame its browser received, is checked for the condition, the stimulus
and the scoring; neither page logged an error. Usage: study_browser_test.py PALPA PALPA_SIM OUT_DIR"""
import json
import os
import sys
import tempfile
import time

from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select, WebDriverWait

from harness import Serve, Sim, chromium, fail, no_console_errors, session_on_disk

STUDY = {
    "schema": "palpa-study", "schema_version": 1, "name": "three-web",
    "description": "Three conditions once each, in a fixed order: the browser test's study.",
    "finger_kind": "pneumatic", "fingers": 3, "unit": "kPa", "cap_kpa": 40,
    "reset": {"hold_ms": 300},
    "conditions": [{"values": [0, 30, 0]}, {"values": [10, 10, 10]}, {"values": [30, 30, 0]}],
    "blocks": [{"name": "at-once", "mode": "simultaneous", "randomise": False}],
}
SECRETS = ["condition", "stimulus", "expected", "correct", "0-30-0", "10-10-10", "30-30-0",
           "kPa", "at-once"]


def visible(driver, element_id):
    return driver.find_element(By.ID, element_id).is_displayed()


def check_shown(driver, seen):
    """The page's text now: nothing of the condition."""
    body = driver.find_element(By.TAG_NAME, "body").text
    seen.append(body)
    for secret in SECRETS:
        if secret in body:
            fail(f"the participant's page showed {secret!r}: {body!r}")


def frames_received(driver):
    """The payloads of every WebSocket frame the browser received (Chrome's performance log)."""
    frames = []
    for entry in driver.get_log("performance"):
        m = json.loads(entry["message"])["message"]
        if m["method"] == "Network.webSocketFrameReceived":
            frames.append(m["params"]["response"]["payloadData"])
    return frames


def main():
    palpa, palpa_sim, out = sys.argv[1], sys.argv[2], sys.argv[3]
    began = time.monotonic()
    os.makedirs(out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="palpa-study-browser-")
    study_file = os.path.join(tmp, "three-web.json")
    with open(study_file, "w") as f:
        json.dump(STUDY, f)
    sessions = os.path.join(tmp, "sessions")
    sim = Sim(palpa_sim, "thesis-pneumatic-3")
    serve = Serve(palpa, sim.address, extra=["--study-dir", sessions, "--study", study_file])
    driver = chromium("1000,800", performance_log=True)
    experimenter = chromium("1000,800", performance_log=True)
    try:
        wait = WebDriverWait(driver, 20)
        driver.get(f"http://{serve.authority}/participant.html")
        wait.until(lambda d: "Waiting for the session to start" in d.find_element(By.ID, "p-end").text)
        experimenter.get(f"http://{serve.authority}/study.html")
        ewait = WebDriverWait(experimenter, 20)
        ewait.until(lambda d: "three-web" in d.find_element(By.ID, "e-study").text)
        Select(experimenter.find_element(By.ID, "e-study")).select_by_value("three-web")
        experimenter.find_element(By.ID, "e-participant").send_keys("B01")
        experimenter.find_element(By.ID, "e-start").click()  # takes control, then starts
        ewait.until(lambda d: "running" in d.find_element(By.ID, "e-status").text)
        seen = []
        for trial, clicks in enumerate([["Finger 2", "p-here"], ["p-none"]]):
            wait.until(lambda d: visible(d, "p-ask"))
            check_shown(driver, seen)
            if f"Trial {trial + 1} of 3" not in driver.find_element(By.ID, "p-progress").text:
                fail(f"progress: {driver.find_element(By.ID, 'p-progress').text}")
            for c in clicks:
                if c.startswith("Finger"):
                    driver.find_element(By.XPATH, f"//button[text()='{c}']").click()
                else:
                    driver.find_element(By.ID, c).click()
            wait.until(lambda d: visible(d, "p-wait"))  # "please wait" while the next settles
            check_shown(driver, seen)
        print("ok  two trials answered by clicking the participant's page")
        ewait.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#e-trials tbody tr.right")) == 2)
        table = experimenter.find_element(By.ID, "e-trials").text
        if "0-30-0" not in table or "tumour: 2" not in table or "10-10-10" not in table:
            fail(f"the experimenter's table: {table}")
        if "trigger: " not in experimenter.find_element(By.ID, "e-trigger").text:
            fail("the experimenter's page shows no trigger")
        print("ok  the experimenter's table filled as the trials were answered, both correct")
        wait.until(lambda d: visible(d, "p-ask"))
        driver.save_screenshot(os.path.join(out, "study_participant.png"))
        sim.wait(lambda s: any(l["chamber_pa"] > 5000 for l in s["lines"]), "trial 3 shown")
        driver.find_element(By.ID, "p-stop").click()
        vented = sim.wait(lambda s: all(abs(l["chamber_pa"]) < 500 for l in s["lines"])
                          and all(f["deformation_mm"] < 0.05 for f in s["fingers"]),
                          "every finger vented after the stop button", 3)
        wait.until(lambda d: "Stopped" in d.find_element(By.ID, "p-end").text)
        check_shown(driver, seen)
        print(f"ok  the stop button vented every line (≤ "
              f"{max(abs(l['chamber_pa']) for l in vented['lines']):.0f} Pa)")
        session, trials = session_on_disk(os.path.join(sessions, "three-web", "B01"))
        complete = session["complete"]
        if complete or [t["condition"] for t in trials] != ["0-30-0", "10-10-10"]:
            fail(f"the journal after the stop: complete {complete}, {trials}")
        if trials[0]["answer"]["fingers"] != [False, True, False] or trials[1]["answer"]["tumour"]:
            fail(f"the answers clicked are not the answers kept: {trials}")
        frames = frames_received(driver)
        if not any("notify_study_participant" in f for f in frames):
            fail("the performance log holds none of the page's frames")
        for frame in frames:
            for secret in SECRETS:
                if secret in frame:
                    fail(f"the participant's socket received {secret!r}: {frame}")
        no_console_errors(driver, "participant's")
        print(f"ok  {len(seen)} views and {len(frames)} frames received: no condition, stimulus "
              "or score; no console error")
        # The experimenter's view of the stopped session, reloaded: the table, the provenance.
        ewait.until(lambda d: "stopped" in d.find_element(By.ID, "e-status").text)
        experimenter.refresh()
        ewait.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#e-trials tbody tr")) == 2)
        ewait.until(lambda d: "stopped" in d.find_element(By.ID, "e-status").text)
        if "firmware" not in experimenter.find_element(By.ID, "e-provenance").text:
            fail("no provenance shown")
        experimenter.save_screenshot(os.path.join(out, "study_experimenter.png"))
        no_console_errors(experimenter, "experimenter's")
        print("ok  the experimenter's view reloaded: the session's trials, its end, its provenance")
    finally:
        driver.quit()
        experimenter.quit()
        serve.close()
        sim.close()
    print(f"study_browser_test: the participant's view in chromium, {time.monotonic() - began:.1f} s")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The page in a real browser (Debian's chromium, headless, through chromium-driver and
python3-selenium) against `palpa serve` and palpa-sim: it sees the board, takes control, moves a
finger from its control, drags the pointer across a scene's map (the finger over an inclusion
stiffens), stops every line with the E-stop key, and when the browser freezes (no
pongs) or the tab closes the board is released — each checked on palpa-sim's truth channel.
Screenshots go to OUT_DIR. Usage: browser_test.py PALPA PALPA_SIM OUT_DIR"""
import os
import signal
import sys
import time

from selenium.webdriver.common.by import By
from selenium.webdriver.common.actions.action_builder import ActionBuilder
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import Select, WebDriverWait

from harness import Serve, Sim, chromium, fail, no_console_errors


def descendants(pid):
    found, queue = [], [pid]
    while queue:
        for child in os.popen(f"pgrep -P {queue.pop()}").read().split():
            found.append(int(child))
            queue.append(int(child))
    return found


def text(driver, element_id):
    return driver.find_element(By.ID, element_id).text


def scene_point(driver, x_mm, y_mm):
    """Where a point of the tissue is in the viewport."""
    return driver.execute_script(
        "const r = document.getElementById('scene-map').getBoundingClientRect();"
        "const [x, y] = scenePixel(arguments[0], arguments[1]);"
        "return [Math.round(r.left + x), Math.round(r.top + y)];", x_mm, y_mm)


def drag_scene(driver, sim, wait, out):
    """Loads the three-cube preset, starts it and drags the mouse along the phantom's mid-line
    (y = 15 mm): with the hand at x = 45 mm finger 2 (15 mm to its right) lies over cube B and
    finger 1 over the soft matrix; at x = 60 mm the two change places. The finger over the cube is
    the stiffer on the simulator's truth channel, both times."""
    Select(driver.find_element(By.ID, "scene-choice")).select_by_value("preset:thesis-three-cube")
    driver.find_element(By.ID, "scene-load").click()
    wait.until(lambda d: "thesis-three-cube" in text(d, "scene-name"))
    driver.execute_script("window.scrollTo(0, 0)")
    driver.find_element(By.ID, "scene-start").click()
    wait.until(lambda d: text(d, "scene-running") == "running")
    actions = ActionBuilder(driver)
    pointer = actions.pointer_action
    pointer.move_to_location(*scene_point(driver, 10, 15))
    pointer.pointer_down()
    for x in range(12, 46, 2):
        pointer.move_to_location(*scene_point(driver, x, 15))
        pointer.pause(0.02)
    actions.perform()

    def stiffer(first, second):  # deformation grows with the rendered stiffness
        return lambda s: (s["fingers"][first]["deformation_mm"]
                          > s["fingers"][second]["deformation_mm"] + 0.3)
    at45 = sim.wait(stiffer(1, 0), "finger 2 over cube B, finger 1 on the matrix")
    wait.until(lambda d: "touches" in text(d, "scene-fingers"))
    driver.save_screenshot(os.path.join(out, "serve_scene.png"))
    actions = ActionBuilder(driver)
    for x in range(46, 61, 1):
        actions.pointer_action.move_to_location(*scene_point(driver, x, 15))
        actions.pointer_action.pause(0.02)
    actions.perform()
    at60 = sim.wait(stiffer(0, 1), "finger 1 over cube B, finger 2 on the matrix")
    print("ok  dragged across the scene: over cube B finger 2 "
          f"{at45['fingers'][1]['deformation_mm']:.2f} mm against finger 1's "
          f"{at45['fingers'][0]['deformation_mm']:.2f}; then finger 1 "
          f"{at60['fingers'][0]['deformation_mm']:.2f} mm against finger 2's "
          f"{at60['fingers'][1]['deformation_mm']:.2f}")
    actions = ActionBuilder(driver)
    actions.pointer_action.pointer_up()
    actions.perform()
    driver.find_element(By.ID, "scene-stop").click()
    wait.until(lambda d: text(d, "scene-running") == "stopped")
    sim.wait(lambda s: all(f["deformation_mm"] < 0.5 for f in s["fingers"][:3]),
             "every finger soft after the scene stopped")
    print("ok  the scene stopped: every finger soft")
    no_console_errors(driver, "board's")


def main():
    palpa, palpa_sim, out = sys.argv[1], sys.argv[2], sys.argv[3]
    os.makedirs(out, exist_ok=True)
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address)
    driver = chromium()
    try:
        driver.get(f"http://{serve.authority}/")
        wait = WebDriverWait(driver, 20)
        wait.until(lambda d: "thesis-5finger" in text(d, "board"))
        wait.until(lambda d: text(d, "out0").endswith("mm"))  # telemetry arrives
        print(f"ok  the page sees the board: {text(driver, 'board')}")
        shown = driver.execute_script(
            "return fromOne('finger 0 does not exist (this board has fingers 0 to 4); line 6: x')")
        if shown != "finger 1 does not exist (this board has fingers 1 to 5); line 7: x":
            fail(f"the page numbers the server's messages wrongly: {shown}")
        driver.find_element(By.ID, "take").click()
        wait.until(lambda d: text(d, "control") == "you control the board")
        driver.find_element(By.CSS_SELECTOR, "#fingers .card:first-child [data-level='2']").click()
        moved = sim.wait(lambda s: s["fingers"][0]["deformation_mm"] > 0.5,
                         "finger 1 to level 2 from the page")
        print(f"ok  finger 1 moved from the page: {moved['fingers'][0]['deformation_mm']} mm")
        time.sleep(1.5)  # a plot's worth of telemetry
        driver.save_screenshot(os.path.join(out, "serve_page.png"))
        drag_scene(driver, sim, wait, out)
        # The E-stop on its key, from wherever the focus is.
        driver.find_element(By.TAG_NAME, "body").send_keys(Keys.SPACE)
        stopped = sim.wait(lambda s: s["board"]["safe"] and s["board"]["faults"] != 0,
                           "the E-stop key")
        wait.until(lambda d: "estop_command" in text(d, "faults"))
        print(f"ok  Space stopped every line: faults {stopped['board']['faults']}")
        driver.save_screenshot(os.path.join(out, "serve_estop.png"))
        driver.find_element(By.ID, "clear").click()
        sim.wait(lambda s: s["board"]["faults"] == 0, "clear")
        driver.find_element(By.CSS_SELECTOR, "#fingers .card:first-child [data-level='1']").click()
        sim.wait(lambda s: not s["board"]["safe"], "level 1 after clear")
        # A frozen browser answers no pings: the server releases the board after three.
        children = descendants(driver.service.process.pid)  # the browser, its network service
        for p in children:
            os.kill(p, signal.SIGSTOP)
        frozen_at = sim.latest()["board_time_us"]
        released = sim.wait(lambda s: s["board"]["safe"], "the release of a frozen page")
        for p in children:
            os.kill(p, signal.SIGCONT)
        waited_ms = (released["board_time_us"] - frozen_at) / 1000
        if released["board"]["faults"] != 0:
            fail(f"the release latched a fault: {released['board']}")
        if waited_ms < 200:
            fail(f"released {waited_ms} ms after freezing: before three pings could be missed")
        print(f"ok  a frozen browser released after {waited_ms:.0f} ms of board time, no fault")
        wait.until(lambda d: text(d, "link") == "connected" and "Finger 1" in text(d, "fingers")
                   and text(d, "control") == "nobody controls the board")
        print("ok  the page came back as a watcher: reconnecting restored nothing")
        driver.save_screenshot(os.path.join(out, "serve_released.png"))
        # Closing the tab while in control releases at once.
        driver.find_element(By.ID, "take").click()
        wait.until(lambda d: text(d, "control") == "you control the board")
        driver.find_element(By.CSS_SELECTOR, "#fingers .card:nth-child(2) [data-level='2']").click()
        sim.wait(lambda s: not s["board"]["safe"], "finger 2 from the page")
        driver.quit()
        driver = None
        closed = sim.wait(lambda s: s["board"]["safe"], "the release when the tab closed")
        print(f"ok  closing the tab released the board (faults {closed['board']['faults']})")
        if not serve.alive():
            fail("the server died")
    finally:
        if driver is not None:
            driver.quit()
        serve.close()
        sim.close()
    print("browser_test: the page saw, moved, stopped and released the board")


if __name__ == "__main__":
    main()

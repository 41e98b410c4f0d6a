#!/usr/bin/python3
"""--device serve:HOST:PORT: the command line and the Python module reach a board through a running
`palpa serve` — reading needs nothing, acting takes control (refused while another client holds
it), E-stop is everyone's, and a command's end gives control up and the board is released.
Numbers as each side numbers: the command line from 1, Python and C from 0. Checked on palpa-sim's
truth channel. Usage: remote_test.py PALPA PALPA_SIM PYTHON_PACKAGE_DIR SERVE_C_TEST"""
import json
import subprocess
import sys

from harness import Client, Serve, Sim, fail, settle


def cli(palpa, device, *args, check=True):
    r = subprocess.run([palpa, "--device", device, "--json", *args], capture_output=True,
                       text=True, timeout=60)
    if check and r.returncode != 0:
        fail(f"palpa {' '.join(args)} exited {r.returncode}: {r.stdout} {r.stderr}")
    return r


def command_line(palpa, device, sim):
    for uri, words in (("serve:127.0.0.1", "expected serve:HOST:PORT"),
                       ("serve:127.0.0.1:1", "nothing listens there")):
        r = cli(palpa, uri, "info", check=False)
        if r.returncode != 3 or words not in r.stdout:
            fail(f"--device {uri}: {r.returncode} {r.stdout}")
        print(f"ok  --device {uri}: {json.loads(r.stdout)['error']['message']}")
    info = json.loads(cli(palpa, device, "info").stdout)
    if info["board"]["configuration"] != "thesis-5finger" or info["fingers"][0]["finger"] != 1:
        fail(f"palpa info through the server: {info}")
    print(f"ok  palpa info through the server: {info['board']['configuration']}, fingers from 1")
    diag = json.loads(cli(palpa, device, "diag").stdout)
    if "loop" not in diag or "link" not in diag:
        fail(f"palpa diag through the server: {diag}")
    print("ok  palpa diag through the server")
    bad = cli(palpa, device, "set", "6=L1", check=False)
    error = json.loads(bad.stdout)["error"]["message"]
    if bad.returncode != 2 or "finger 6" not in error or "1 to 5" not in error:
        fail(f"a finger the board lacks, through the server: {bad.returncode} {bad.stdout}")
    print(f"ok  palpa set 6=L1 refused, numbered as the command line numbers: {error}")
    held = subprocess.Popen([palpa, "--device", device, "set", "1=L2", "--hold", "3"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    moved = sim.wait(lambda s: s["fingers"][0]["deformation_mm"] > 0.5, "palpa set 1=L2")
    print(f"ok  palpa set 1=L2 --hold 3 through the server: {moved['fingers'][0]['deformation_mm']} mm")
    monitor = cli(palpa, device, "monitor", "--duration", "1", "--rate", "100")
    samples = [json.loads(line) for line in monitor.stdout.splitlines()]
    if len(samples) < 50 or samples[-1]["finger_output"][0] < 0.5:
        fail(f"palpa monitor through the server while another controls: {len(samples)} samples")
    print(f"ok  palpa monitor watched beside it: {len(samples)} samples in 1 s, finger 1 at "
          f"{samples[-1]['finger_output'][0]:.2f} mm")
    busy = cli(palpa, device, "set", "2=L1", check=False)
    if busy.returncode == 0 or json.loads(busy.stdout)["error"]["status"] != "busy":
        fail(f"a second controller through the server: {busy.returncode} {busy.stdout}")
    print(f"ok  a second palpa set refused while the first holds control: "
          f"{json.loads(busy.stdout)['error']['message']}")
    out, err = held.communicate(timeout=30)
    if held.returncode != 0:
        fail(f"palpa set --hold exited {held.returncode}: {out} {err}")
    sim.wait(lambda s: s["board"]["safe"], "the release when palpa set ended")
    print("ok  palpa set's end gave control up: the board released")
    unsupported = cli(palpa, device, "calibrate", "--finger", "1", check=False)
    if unsupported.returncode != 2:
        fail(f"calibrate through the server: {unsupported.returncode} {unsupported.stdout}")
    print(f"ok  a command that cannot go through the server says so: "
          f"{json.loads(unsupported.stdout)['error']['message']}")


def python_module(package_dir, device, sim):
    sys.path.insert(0, package_dir)
    import palpa
    with palpa.Device(device) as watcher, palpa.Device(device) as controller:
        if type(watcher).__name__ != "ServeDevice" or watcher.info()["fingers"][3] != "jamming":
            fail(f"palpa.Device('{device}'): {type(watcher)} {watcher.info()}")
        controller.set(0, level=2)
        sim.wait(lambda s: s["fingers"][0]["deformation_mm"] > 0.5, "Python's set(0, level=2)")
        samples = list(watcher.monitor(seconds=0.5))
        if len(samples) < 200 or samples[-1]["finger_output"][0] < 0.5:
            fail(f"a Python watcher's monitor: {len(samples)} samples")
        print(f"ok  Python: one controls (finger 0 at {samples[-1]['finger_output'][0]:.2f} mm), "
              f"another watches ({len(samples)} samples in 0.5 s)")
        try:
            watcher.set(1, level=1)
            fail("a Python watcher took control from the controller")
        except palpa.PalpaError as e:
            if e.status != "busy":
                fail(f"a Python watcher's set: {e.status} {e}")
            print(f"ok  Python: the watcher's set refused ({e.status}): {e}")
        try:
            controller.set(7, level=1)
            fail("a finger the board lacks was accepted")
        except ValueError as e:  # as palpa.Device says it, numbered from 0
            if "finger 7 does not exist: this board has fingers 0 to 4" not in str(e):
                fail(f"a finger the board lacks, numbered from 0: {e}")
        watcher.estop()
        sim.wait(lambda s: s["board"]["safe"] and s["board"]["faults"] != 0, "a watcher's E-stop")
        controller.clear_fault()
        controller.set(0, level=1)
        sim.wait(lambda s: not s["board"]["safe"], "set after clear")
        print("ok  Python: the watcher's E-stop stopped every line; the controller cleared it")
    sim.wait(lambda s: s["board"]["safe"] and s["board"]["faults"] == 0,
             "the release when the Python controller closed")
    print("ok  Python: closing gave control up and the board was released")


def c_abi(serve_c_test, device, sim):
    """serve_c_test.c's scenario (its own checks), then the board as closing leaves it."""
    r = subprocess.run([serve_c_test, device], capture_output=True, text=True, timeout=60)
    print(r.stdout, end="")
    if r.returncode != 0:
        fail(f"the C ABI through the server exited {r.returncode}: {r.stderr}")
    sim.wait(lambda s: s["board"]["safe"] and s["board"]["faults"] == 0,
             "the board released, no fault, when the C handles closed")
    print("ok  C: closing left the board released, no fault latched")


def main():
    palpa, palpa_sim, package_dir, serve_c_test = sys.argv[1:5]
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address)
    device = f"serve:127.0.0.1:{serve.port}"
    try:
        command_line(palpa, device, sim)
        python_module(package_dir, device, sim)
        c_abi(serve_c_test, device, sim)
        if not serve.alive():
            fail("the server died")
    finally:
        serve.close()
        sim.close()
    print("remote_test: the command line, Python and C watched and controlled through palpa serve")


if __name__ == "__main__":
    main()

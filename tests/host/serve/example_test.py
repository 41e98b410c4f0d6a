#!/usr/bin/python3
"""docs/examples/serve_client.py against a running `palpa serve`: the documented script works, and
what it did shows on palpa-sim's truth channel. Usage: example_test.py PALPA PALPA_SIM EXAMPLE"""
import subprocess
import sys

from harness import Serve, Sim, fail


def main():
    palpa, palpa_sim, example = sys.argv[1:4]
    sim = Sim(palpa_sim)
    serve = Serve(palpa, sim.address)
    try:
        run = subprocess.run(["/usr/bin/python3", example, f"ws://{serve.authority}"],
                             capture_output=True, text=True, timeout=60)
        print(run.stdout, run.stderr)
        if run.returncode != 0 or "finger 0: target 1.164 mm" not in run.stdout:
            fail(f"the example failed (exit {run.returncode})")
        moved = max(s["fingers"][0]["deformation_mm"] for s in sim.since(0))
        if moved < 0.5:
            fail(f"the example's level 2 never moved finger 0 (at most {moved} mm)")
        if not sim.latest()["board"]["safe"]:
            fail("the example gave control back but the board was not released")
    finally:
        serve.close()
        sim.close()
    print("example_test: docs/examples/serve_client.py works as documented")


if __name__ == "__main__":
    main()

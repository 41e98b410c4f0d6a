#!/usr/bin/python3
"""CTest for scenes and several-finger requests from Python, on palpa-sim: a scene file opened on a
device, samples fed without waiting with each finger's render returned, a lifted hand releasing
every finger, telemetry drained without waiting, several fingers set in one call, and clear
errors for wrong requests."""
import os

from palpa_checks import palpa, refused, REPO

EXAMPLE = os.path.join(REPO, "docs", "examples", "scene_three_cube.json")
INPUTS = os.path.join(REPO, "docs", "examples", "scene_inputs.json")


def main():
    with palpa.Device("sim:thesis-pneumatic-3") as board:
        with palpa.Scene(board, EXAMPLE) as scene:
            renders = scene.feed(60, 12, 1.0, time_s=0)  # finger 0 on cube B
            assert [r["finger"] for r in renders] == [0, 1, 2], renders
            assert renders[0]["touching"] and renders[0]["u"] > 0.99, renders[0]
            assert renders[0]["unit"] == "mm" and renders[0]["target"] > renders[1]["target"], renders
            lifted = scene.feed(60, 12, 0.0, time_s=0.01)
            assert all(not r["touching"] and r["target"] == 0 for r in lifted), lifted
            assert all(not r["touching"] for r in scene.feed(float("nan"), 12, 1.0))
            refused(TypeError, lambda: scene.feed("60", 12, 1.0), "x_mm must be a number")
        with palpa.Scene(board, INPUTS) as scene:
            renders = scene.feed_tactile([36, 40, 44, 10, 20, 30, 0, 0, 0])
            assert abs(renders[0]["u"] - 1) < 1e-9 and abs(renders[1]["u"] - 0.5) < 1e-9, renders
            assert renders[2]["target"] == 0, renders
            assert all(not r["touching"] for r in scene.feed_tactile(None))
            refused(palpa.PalpaError, lambda: scene.feed_tactile([1, 2]), "2 values, the scene's array has 9")
            refused(TypeError, lambda: scene.feed_tactile(["a"] * 9), "values[0] must be a number")
            refused(palpa.PalpaError, lambda: scene.predict(), "line 1 has no chamber model")
            assert scene.predict(False) is None
            refused(palpa.PalpaError, lambda: palpa.Tablet(scene, "/dev/null"),
                    "/dev/null: not an input event device")
        samples = list(board.monitor(seconds=0))  # drained without waiting
        assert isinstance(samples, list)
        refused(palpa.PalpaError, lambda: palpa.Scene(board, "/nonexistent/scene.json"),
                "not_found", "/nonexistent/scene.json")
        board.set_fingers([(0, "mm", 1.0), (1, "level", 1), (2, "normalized", 0.5)], wait=True)
        board.set_fingers([(0, "mm", 0.5), (1, "mm", 0.5), (2, "mm", 0.5)])
        refused(palpa.PalpaError, lambda: board.set_fingers([(0, "mm", 1.0), (1, "n_per_mm", 1.0)]),
                "bad_value", "finger 1: N/mm means nothing")
        refused(ValueError, lambda: board.set_fingers([(0, "stiff", 1.0)]), "requests[0]: kind 'stiff'")
        refused(ValueError, lambda: board.set_fingers([(7, "mm", 1.0)]), "finger 7 does not exist")
        refused(ValueError, lambda: board.set_fingers([]), "1 to 8 requests")
    print("test_scene: ok")


if __name__ == "__main__":
    main()

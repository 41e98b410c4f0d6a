#!/usr/bin/python3
"""A Python application's sessions: open, set, close (with), reopen and set; a second device
while one is held is told busy; a refusal for a latched fault names it in PalpaError.faults.
    close_reopen.py URI        (PALPA_LIBRARY: the path of libpalpa.so)"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../host/lib/python"))
import palpa  # noqa: E402


def main(uri):
    with palpa.Device(uri) as board:
        board.set(0, level=2)
        try:
            palpa.Device(uri)
            raise AssertionError("a second device while the first is held must be refused")
        except palpa.PalpaError as e:
            assert e.status == "busy" and "busy: another host holds the board" in str(e), e
    time.sleep(0.2)  # twice the board's host-silence timeout: the with block closed the session

    board = palpa.Device(uri)
    assert board.info()["fault_bitmap"] == 0, board.info()  # a Close is no fault
    board.set(0, level=2)
    board.release()  # outputs safe, session kept
    board.set(0, level=1)
    board.estop()
    try:
        board.set(0, level=2)
        raise AssertionError("a set after an E-stop must be refused")
    except palpa.PalpaError as e:
        assert e.status == "faulted" and e.faults == ["estop_command"], (e, e.faults)
        assert "estop_command, latched at board time" in str(e) and "Clear the fault" in str(e), e
    board.clear_fault()
    board.set(0, level=1)
    board.close()
    try:
        board.set(0, level=1)
        raise AssertionError("a closed device must refuse")
    except palpa.PalpaError as e:
        assert e.status == "no_session", e
    del board  # closing twice (close, then collection) is harmless

    forgotten = palpa.Device(uri)  # never closed by hand: collected, and closed with it
    forgotten.set(0, level=2)
    del forgotten
    with palpa.Device(uri) as board:  # at once: the collected device's Close freed the board
        assert board.info()["fault_bitmap"] == 0
    print("close_reopen.py: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))

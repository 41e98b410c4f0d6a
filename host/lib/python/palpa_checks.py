"""What the Python module's CTests share: the palpa package of this source tree (not an installed
one), the repository's root for its data and examples, and `refused`."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import palpa  # noqa: E402,F401  (the tests take it from here)

REPO = os.path.join(HERE, "..", "..", "..")


def refused(error_type, call, *words):
    """call() raises error_type with every word in its message."""
    try:
        call()
    except error_type as e:
        for word in words:
            assert word in str(e), (word, str(e))
        return
    raise AssertionError(f"expected {error_type.__name__} with {words}")

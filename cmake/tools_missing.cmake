# The test that stands for the tests a missing program keeps from running: it always fails.
message(FATAL_ERROR "missing: ${MISSING}. The tests that need them are not registered; install "
                    "them (./run test does) and build again.")

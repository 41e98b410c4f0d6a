# Runs a self-test image under QEMU (deterministic: -icount) and checks its exit code and output.
# -DQEMU= -DIMAGE= -DEXPECT_CODE= -DEXPECT_TEXT=
if(NOT EXISTS ${IMAGE})
  message(FATAL_ERROR "${IMAGE} is missing: build the mps2 preset first (./run test does)")
endif()
execute_process(COMMAND ${QEMU} -M mps2-an386 -nographic -monitor none -serial null
                        -semihosting-config enable=on,target=native -icount shift=3,sleep=off -kernel ${IMAGE}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
string(APPEND out "${err}")  # semihosting writes to QEMU's stderr
message(STATUS "${out}")
if(NOT rc EQUAL EXPECT_CODE)
  message(FATAL_ERROR "exit code ${rc}, expected ${EXPECT_CODE}\n${out}\n${err}")
endif()
if(NOT out MATCHES "${EXPECT_TEXT}")
  message(FATAL_ERROR "output does not contain '${EXPECT_TEXT}':\n${out}")
endif()

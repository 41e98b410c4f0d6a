# Builds a deliberately bad image and expects the symbol check to reject it.
# An object is enough: what it needs from libraries shows as undefined symbols.
execute_process(COMMAND ${CXX} -mcpu=cortex-m4 -mthumb -mfloat-abi=soft -O1 -c ${SOURCE} -o ${WORK}/bad_image.elf
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "could not build the bad image: ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -DIMAGE=${WORK}/bad_image.elf -DNM=${NM} -P ${CHECK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "the symbol check accepted a bad image:\n${out}")
endif()
if(NOT out MATCHES "__aeabi_d" OR NOT out MATCHES "_Znw")
  message(FATAL_ERROR "the symbol check failed for the wrong reason:\n${out}")
endif()
message(STATUS "the symbol check rejects a bad image")

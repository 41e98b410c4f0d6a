# Compiler flags shared by every palpa target: warnings, freestanding layers, sanitizers.

set(PALPA_WARNINGS -Wall -Wextra -Werror -Wshadow)
# The freestanding layers also refuse silent narrowing: a truncated pressure is a safety bug.
set(PALPA_STRICT_WARNINGS -Wconversion -Wno-sign-conversion)

# Flags of the target side. protocol/ and firmware/core compile with them on every build, so a
# heap allocation or an exception is a build error on the host too.
set(PALPA_FREESTANDING_FLAGS -ffreestanding -fno-exceptions -fno-rtti -fno-threadsafe-statics
    -fno-use-cxa-atexit)

function(palpa_warnings target)
  target_compile_options(${target} PRIVATE ${PALPA_WARNINGS})
endfunction()

function(palpa_freestanding target)
  target_compile_options(${target} PRIVATE ${PALPA_FREESTANDING_FLAGS} ${PALPA_STRICT_WARNINGS})
endfunction()

if(PALPA_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

# The tsan preset: the host library's reader thread, heartbeat and subscribers under
# ThreadSanitizer (it cannot share a build with ASan).
if(PALPA_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

# The fuzz preset instruments every library for libFuzzer's coverage and the sanitizers, so a
# fuzz target is guided through the code it drives, not only through its own file; the targets
# themselves link -fsanitize=fuzzer.
if(PALPA_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all)
  add_link_options(-fsanitize=address,undefined)
  # CppUTest's leak detector replaces operator new, which clang's ASan runtime also defines: the
  # unit tests this preset builds alongside the fuzzers rely on ASan's leak checks instead.
  add_compile_definitions(CPPUTEST_MEM_LEAK_DETECTION_DISABLED)
endif()

# A hand-scheduled ARMv7E-M routine on the MCU: assembles `asm_source` into `target` and defines
# `define` for `user_source`, the C++ file that calls it; the host build keeps the portable loop.
# A macro, because enable_language must run in the directory's scope.
macro(palpa_armv7em_routine target asm_source user_source define)
  if(CMAKE_SYSTEM_PROCESSOR STREQUAL "arm")
    enable_language(ASM)
    target_sources(${target} PRIVATE ${asm_source})
    set_source_files_properties(${user_source} PROPERTIES COMPILE_DEFINITIONS ${define}=1)
  endif()
endmacro()

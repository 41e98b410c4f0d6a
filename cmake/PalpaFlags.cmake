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

# Programs some tests need (QEMU, the ARM toolchain, clang-format). A missing one never passes
# silently: it is named when configuring, the test `tools_missing` fails naming it in every ctest
# run, and with PALPA_REQUIRE_TOOLS (what ./run test sets) configuring stops. Installing it later
# re-runs the configuration by itself: while a tool is missing, the build depends on the
# directories it could appear in, so the tests it enables are registered at the next build.

set(_palpa_tools_dir ${CMAKE_CURRENT_LIST_DIR})
option(PALPA_REQUIRE_TOOLS "Stop configuring when a program a test needs is missing (./run test)" OFF)

# palpa_find_tool(VAR PROGRAM WHAT): find_program(VAR PROGRAM); WHAT says what needs it.
function(palpa_find_tool var program what)
  find_program(${var} ${program})
  if(${var})
    return()
  endif()
  get_property(missing GLOBAL PROPERTY PALPA_MISSING_TOOLS)
  if(NOT "${program}" IN_LIST missing)
    set_property(GLOBAL APPEND PROPERTY PALPA_MISSING_TOOLS "${program}")
    set_property(GLOBAL APPEND PROPERTY PALPA_MISSING_TOOLS_WHY "${program} (${what})")
  endif()
  if(PALPA_REQUIRE_TOOLS)
    message(FATAL_ERROR "${program} is missing: ${what} cannot run. Install it (./run test "
                        "installs every tool) or configure without PALPA_REQUIRE_TOOLS.")
  endif()
  message(STATUS "${program} is missing: ${what} cannot run; the test tools_missing fails "
                  "until it is installed (the next build notices it by itself)")
  # Where apt or a person puts a program: a change in any of these directories re-runs CMake.
  set(dirs /usr/bin /usr/local/bin)
  if(DEFINED ENV{PATH})
    string(REPLACE ":" ";" path_dirs "$ENV{PATH}")
    list(APPEND dirs ${path_dirs})
  endif()
  list(REMOVE_DUPLICATES dirs)
  foreach(dir IN LISTS dirs)
    if(IS_ABSOLUTE "${dir}" AND IS_DIRECTORY "${dir}")
      set_property(DIRECTORY "${CMAKE_SOURCE_DIR}" APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${dir}")
    endif()
  endforeach()
endfunction()

# After every palpa_find_tool: a failing test naming what is missing, if anything is.
function(palpa_add_tools_test)
  get_property(why GLOBAL PROPERTY PALPA_MISSING_TOOLS_WHY)
  if(NOT why)
    return()
  endif()
  string(REPLACE ";" ", " why "${why}")
  add_test(NAME tools_missing
           COMMAND ${CMAKE_COMMAND} "-DMISSING=${why}" -P ${_palpa_tools_dir}/tools_missing.cmake)
endfunction()

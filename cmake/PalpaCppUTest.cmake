# CppUTest through pkg-config, and one CTest entry per test group (discovered after the build,
# keeping labels and RUN_SERIAL, which CppUTest's own discovery script drops).
find_package(PkgConfig REQUIRED)
pkg_check_modules(CPPUTEST REQUIRED IMPORTED_TARGET cpputest)

# palpa_add_cpputest(NAME SOURCES ... LIBS ... [LABELS ...] [SERIAL_GROUPS ...] [LONG_GROUPS ...])
# LONG_GROUPS run for a minute or more in some preset (calibrations in real time; in-process ones
# under the sanitizers): CTest starts them first, so the short groups fill the other processor
# meanwhile rather than leaving a long one running alone at the end.
function(palpa_add_cpputest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS;SERIAL_GROUPS;LONG_GROUPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES} ${PROJECT_SOURCE_DIR}/tests/support/all_tests_main.cc)
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} PkgConfig::CPPUTEST palpa_development_keys)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
  palpa_warnings(${name})
  # CppUTest's TestHarness.h defines `new` as a macro (file and line for its leak reports), which
  # breaks standard headers included after it: in a unity batch the next file starts with it
  # undone. Leaks are still found there, reported without the file and line.
  set_target_properties(${name} PROPERTIES UNITY_BUILD_CODE_BEFORE_INCLUDE "#undef new")
  set(listing "${CMAKE_CURRENT_BINARY_DIR}/${name}_tests.cmake")
  add_custom_command(TARGET ${name} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -DEXECUTABLE=$<TARGET_FILE:${name}> -DNAME=${name}
            "-DLABELS=${ARG_LABELS}" "-DSERIAL_GROUPS=${ARG_SERIAL_GROUPS}"
            "-DLONG_GROUPS=${ARG_LONG_GROUPS}" -DOUTPUT=${listing}
            -P ${PROJECT_SOURCE_DIR}/cmake/PalpaDiscoverCppUTest.cmake
    VERBATIM)
  # Not built, the suite is one failing entry that keeps its labels, so a preset that runs a label
  # (asan: sanitize) fails rather than leaving the suite out.
  set(loader "${CMAKE_CURRENT_BINARY_DIR}/${name}_include.cmake")
  file(WRITE ${loader}
    "if(EXISTS \"${listing}\")\n  include(\"${listing}\")\nelse()\n"
    "  add_test(${name}_NOT_BUILT ${name}_NOT_BUILT)\n"
    "  set_tests_properties(${name}_NOT_BUILT PROPERTIES LABELS [=[${ARG_LABELS}]=])\nendif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${loader})
  # One target per label builds the suites that carry it (tests_sanitize, tests_threads): a preset
  # that runs one label builds only what it runs.
  foreach(label IN LISTS ARG_LABELS)
    if(NOT TARGET tests_${label})
      add_custom_target(tests_${label})
    endif()
    add_dependencies(tests_${label} ${name})
  endforeach()
endfunction()

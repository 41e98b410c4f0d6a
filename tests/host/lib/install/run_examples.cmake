# Installs the build into a scratch prefix, as a user would anywhere but /usr/local, and runs
# docs/examples against that install only: C built with pkg-config (palpa.pc relocated with its
# prefix), C and C++ with find_package(palpa), the Python package imported from where Debian's
# python3 looks for the prefix with its library found beside it, and the CLI from the prefix's bin.
# -DBUILD_DIR -DEXAMPLES -DWORK -DPYTHON_DIR (relative to the prefix) -DINSTALL_PREFIX
file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}${err}")
  endif()
  if(NOT what STREQUAL "install")
    message(STATUS "${what}:\n${out}${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# Nothing of the build tree or of another palpa may help: only the prefix.
set(clean_env ${CMAKE_COMMAND} -E env --unset=PALPA_SIM --unset=PALPA_LIBRARY --unset=PALPA_DEVICE
    --unset=PALPA_SIM_ARGS --unset=PYTHONPATH PALPA_STATE_DIR=${WORK}/state)
file(GLOB_RECURSE pc_files ${prefix}/*/palpa.pc)
list(GET pc_files 0 pc_file)
get_filename_component(pc_dir ${pc_file} DIRECTORY)
get_filename_component(lib_dir ${pc_dir} DIRECTORY)

# pkg-config: the flags point into this prefix, wherever it is.
run("pkg-config" ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} pkg-config --cflags --libs palpa)
string(STRIP "${out}" flags)
if(NOT flags MATCHES "-I${prefix}" OR flags MATCHES "/usr/local")
  message(FATAL_ERROR "palpa.pc does not follow its prefix: ${flags}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run("cc with pkg-config" cc -std=c11 -Wall -Werror ${EXAMPLES}/c_example.c ${flags} -o ${WORK}/c_example_pc)
# The scene file by its path: a build's __FILE__ may be relative to where it was compiled.
set(scene ${EXAMPLES}/scene_three_cube.json)
run("C example (pkg-config build)" ${clean_env} LD_LIBRARY_PATH=${lib_dir} ${WORK}/c_example_pc ${scene})

# find_package(palpa): the C and C++ examples.
run("configure the examples" ${CMAKE_COMMAND} -S ${EXAMPLES} -B ${WORK}/build -DCMAKE_PREFIX_PATH=${prefix})
run("build the examples" ${CMAKE_COMMAND} --build ${WORK}/build)
run("C example" ${clean_env} LD_LIBRARY_PATH=${lib_dir} ${WORK}/build/c_example ${scene})
run("C++ example" ${clean_env} LD_LIBRARY_PATH=${lib_dir} ${WORK}/build/cpp_example ${scene})

# Python: the package is where Debian's python3 imports from for the configured prefix...
run("python3's path" /usr/bin/python3 -c "print(chr(10).join(__import__('sys').path))")
if(NOT out MATCHES "(^|\n)${INSTALL_PREFIX}/${PYTHON_DIR}(\n|$)")
  message(FATAL_ERROR "${INSTALL_PREFIX}/${PYTHON_DIR} is not where /usr/bin/python3 imports from:\n${out}")
endif()
if(NOT EXISTS ${prefix}/${PYTHON_DIR}/palpa/__init__.py)
  message(FATAL_ERROR "no palpa package in ${prefix}/${PYTHON_DIR}")
endif()
# ...and, under this scratch prefix, finds its library from where it is: no PALPA_LIBRARY, no
# LD_LIBRARY_PATH.
run("Python example" ${clean_env} PYTHONPATH=${prefix}/${PYTHON_DIR} /usr/bin/python3
    ${EXAMPLES}/python_example.py)
# Every module of the package is installed: serve: loads its own only when a script names one.
run("Python modules" ${clean_env} PYTHONPATH=${prefix}/${PYTHON_DIR} /usr/bin/python3 -c
    "import palpa.scene, palpa.serve")

# The command line from the prefix's bin, with a simulated board kept across commands.
run("CLI example" ${clean_env} PATH=${prefix}/bin:$ENV{PATH} sh -e ${EXAMPLES}/cli.sh ${WORK})
if(NOT out MATCHES "configuration thesis-5finger \\(saved\\)")
  message(FATAL_ERROR "the saved configuration did not survive the simulator's restart")
endif()
file(REMOVE_RECURSE ${WORK})

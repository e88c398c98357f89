# ctest Install.ConsumerBuildsAgainstInstalledPackage: installs the build tree into a fresh
# temporary prefix, configures and builds tests/install/ against it, runs the program, the
# installed CLI and the installed Python module. Arguments: -DBUILD_DIR -DSOURCE_DIR -DPYTHON
# -DPYTHON_DIR (the module's directory relative to the prefix).
execute_process(COMMAND mktemp -d /tmp/skelgrasp-install-test.XXXXXX OUTPUT_VARIABLE work
                OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
set(prefix ${work}/prefix)

function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    file(REMOVE_RECURSE ${work})
    message(FATAL_ERROR "${name} failed (${code}):\n${out}\n${err}")
  endif()
  message(STATUS "${name}: ok\n${out}")
endfunction()

step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
step("configure consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install -B ${work}/build
     -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
step("build consumer" ${CMAKE_COMMAND} --build ${work}/build)
step("run consumer" ${work}/build/consumer)
# The installed CLI finds the built-in hands wherever it is.
step("installed CLI" ${prefix}/bin/skelgrasp hands)
if(NOT EXISTS ${prefix}/share/skelgrasp/hands/sdh/sdh.urdf)
  message(FATAL_ERROR "hand files not installed under ${prefix}/share/skelgrasp/hands")
endif()
if(PYTHON_DIR)
  step("installed Python module" ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_DIR}
       ${PYTHON} -c "import skelgrasp; print(skelgrasp.__file__); print(skelgrasp.hand('sdh'))")
endif()
file(REMOVE_RECURSE ${work})

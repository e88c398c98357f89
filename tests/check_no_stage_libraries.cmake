# Fails when BINARY depends on a shared library matching FORBIDDEN (a regex), per `ldd`.
# A program that plans on a mesh (skeleton, grasping, ranking) must not pull in the perception
# stack nor the picture libraries; the launcher and the mesh commands' program have lists of their
# own (tests/CMakeLists.txt).
# Without ldd it stops with "ldd not found", which the test's SKIP_REGULAR_EXPRESSION skips.
find_program(LDD_PROGRAM ldd)
if(NOT LDD_PROGRAM)
  message(FATAL_ERROR "ldd not found: skipping the link check of ${BINARY}")
endif()
execute_process(COMMAND ${LDD_PROGRAM} ${BINARY} OUTPUT_VARIABLE libraries RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ldd ${BINARY} failed (${code})")
endif()
string(REGEX MATCHALL "[^\n\t ]*(${FORBIDDEN})[^\n\t ]*" found "${libraries}")
if(found)
  list(REMOVE_DUPLICATES found)
  message(FATAL_ERROR "${BINARY} links ${found}")
endif()
message("${BINARY}: no library matching ${FORBIDDEN}")

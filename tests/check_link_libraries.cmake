# Fails when TARGET's own link libraries (LIBRARIES, comma-separated: its LINK_LIBRARIES) match
# FORBIDDEN (a regex). Unlike check_no_stage_libraries.cmake, which asks ldd what a program loads,
# this reads what a library links at all, used or not.
string(REPLACE "," ";" libraries "${LIBRARIES}")
set(found "")
foreach(library ${libraries})
  if(library MATCHES "${FORBIDDEN}")
    list(APPEND found ${library})
  endif()
endforeach()
if(found)
  message(FATAL_ERROR "${TARGET} links ${found}")
endif()
message("${TARGET}: links no library matching ${FORBIDDEN}")

# Fails when a module links a skelgrasp module that the tree of docs/architecture.md does not let
# it link. Arguments: -DMODULES=m1,m2,... and, for each module m, -DLINKS_m (its target's
# LINK_LIBRARIES, comma-separated) and -DALLOWED_m (the modules it may link, comma-separated).
cmake_policy(VERSION 3.18)  # IN_LIST
string(REPLACE "," ";" modules "${MODULES}")
set(broken "")
foreach(module ${modules})
  string(REPLACE "," ";" links "${LINKS_${module}}")
  string(REPLACE "," ";" allowed "${ALLOWED_${module}}")
  foreach(link ${links})
    if(link MATCHES "^skelgrasp::(.+)$")
      set(linked ${CMAKE_MATCH_1})
      if(NOT linked IN_LIST allowed)
        list(APPEND broken "${module} -> ${linked}")
      endif()
    endif()
  endforeach()
endforeach()
if(broken)
  message(FATAL_ERROR "links outside the module tree: ${broken}")
endif()
message("every module links only modules below it: ${MODULES}")

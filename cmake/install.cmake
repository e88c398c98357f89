# `cmake --install build --prefix P`: headers, the static libraries with their exported targets
# (skelgrasp::<module>) and skelgrasp-config.cmake, the CLI and the built-in hand files. The Python
# module installs itself (python/CMakeLists.txt). Included once every module's target exists; the
# module CMakeLists.txt files stay as they are.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SKELGRASP_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/skelgrasp)
set(SKELGRASP_EXPORTED_MODULES common geometry geometry_cgal perception reconstruction skeleton
                               grasping physics ranking presentation pipeline evaluation datasets)

foreach(module ${SKELGRASP_EXPORTED_MODULES})
  set(target skelgrasp_${module})
  # The modules name their source include folders; an installed target names <prefix>/include.
  get_target_property(include_dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  set(relocatable "")
  foreach(dir ${include_dirs})
    list(APPEND relocatable "$<BUILD_INTERFACE:${dir}>")
  endforeach()
  list(APPEND relocatable "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")
  set_property(TARGET ${target} PROPERTY INTERFACE_INCLUDE_DIRECTORIES "${relocatable}")
  set_property(TARGET ${target} PROPERTY EXPORT_NAME ${module})
  if(EXISTS ${CMAKE_SOURCE_DIR}/${module}/include)
    install(DIRECTORY ${CMAKE_SOURCE_DIR}/${module}/include/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
  endif()
endforeach()
# geometry's one deliberately shared internal header (skelgrasp/internal/cgal_conversions.h).
install(DIRECTORY ${CMAKE_SOURCE_DIR}/geometry/internal/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)

list(TRANSFORM SKELGRASP_EXPORTED_MODULES PREPEND skelgrasp_ OUTPUT_VARIABLE exported_targets)
install(TARGETS ${exported_targets} EXPORT skelgrasp-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT skelgrasp-targets NAMESPACE skelgrasp:: DESTINATION ${SKELGRASP_INSTALL_CMAKEDIR}
        COMPONENT development)

configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/skelgrasp-config.cmake.in
                              ${CMAKE_BINARY_DIR}/skelgrasp-config.cmake
                              INSTALL_DESTINATION ${SKELGRASP_INSTALL_CMAKEDIR}
                              PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/skelgrasp-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/skelgrasp-config.cmake
              ${CMAKE_BINARY_DIR}/skelgrasp-config-version.cmake
        DESTINATION ${SKELGRASP_INSTALL_CMAKEDIR} COMPONENT development)

# The CLI. The built-in hands are compiled into the library (grasping/CMakeLists.txt), so an
# installed `skelgrasp --hand sdh` needs no files; the hand files are installed beside it for users
# who adapt a hand (load_hand / --hand my.urdf --grasp-description my.grasp.json).
# The launcher and the two command programs it starts from its own directory
# (apps/command_programs.h).
install(TARGETS skelgrasp skelgrasp-mesh skelgrasp-full RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        COMPONENT runtime)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/grasping/hands/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/skelgrasp/hands COMPONENT runtime)

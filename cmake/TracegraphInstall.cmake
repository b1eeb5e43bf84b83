# Installation: headers of every layer and the umbrella, the libraries with a CMake package
# (find_package(Tracegraph CONFIG) -> Tracegraph::tracegraph and the layer targets), and the
# tools. Included at the end of the top-level CMakeLists.txt, once every target exists.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(TG_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Tracegraph CACHE STRING
    "Where the CMake package files of Tracegraph are installed, relative to the prefix")

# The exported names match the in-tree aliases (Tracegraph::backend ...), so that a project can
# move between add_subdirectory and find_package without renaming targets.
set(tg_library_targets)
foreach(layer backend scenegraph nodes loaders)
  if(TARGET tg_${layer})
    set_target_properties(tg_${layer} PROPERTIES EXPORT_NAME ${layer})
    list(APPEND tg_library_targets tg_${layer})
  endif()
endforeach()
list(APPEND tg_library_targets tracegraph)

# The targets already name <prefix>/include as their installed include folder; a different
# CMAKE_INSTALL_INCLUDEDIR needs adding to it.
set(tg_includes "")
if(NOT CMAKE_INSTALL_INCLUDEDIR STREQUAL "include")
  set(tg_includes INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
install(TARGETS ${tg_library_targets}
        EXPORT TracegraphTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        ${tg_includes})

# Public headers: each layer's include/ tree (tracegraph/<layer>/...) and the umbrella.
foreach(dir backend scenegraph nodes loaders tracegraph)
  if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/include)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/include/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            FILES_MATCHING PATTERN "*.h")
  endif()
endforeach()

install(EXPORT TracegraphTargets
        NAMESPACE Tracegraph::
        FILE TracegraphTargets.cmake
        DESTINATION ${TG_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/TracegraphConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/TracegraphConfig.cmake
                              INSTALL_DESTINATION ${TG_INSTALL_CMAKEDIR})
# 0.x: minor versions may break the API, so only the same minor version is compatible.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/TracegraphConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION}
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/TracegraphConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/TracegraphConfigVersion.cmake
        DESTINATION ${TG_INSTALL_CMAKEDIR})

# The tools, when they were built.
foreach(tool tg-render tg-view tg-bench tg-demo)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

# CTest script of packaging.umbrella: every public header of every layer is reachable from
# <tracegraph/tracegraph.h>, directly or through a layer's All.h, so that a header added to a
# layer is not silently missing from the umbrella.
# cmake -DSOURCE_DIR=<repository> -P UmbrellaTest.cmake
cmake_minimum_required(VERSION 3.20)
set(included "")
foreach(file tracegraph/include/tracegraph/tracegraph.h
             scenegraph/include/tracegraph/scenegraph/All.h
             nodes/include/tracegraph/nodes/All.h)
  file(STRINGS "${SOURCE_DIR}/${file}" lines REGEX "^#include \"tracegraph/")
  foreach(line ${lines})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" header "${line}")
    list(APPEND included "${header}")
  endforeach()
endforeach()
set(missing "")
foreach(layer backend scenegraph nodes loaders)
  file(GLOB_RECURSE headers RELATIVE "${SOURCE_DIR}/${layer}/include"
       "${SOURCE_DIR}/${layer}/include/tracegraph/*.h")
  foreach(header ${headers})
    if(NOT header MATCHES "/All\\.h$" AND NOT header IN_LIST included)
      list(APPEND missing "${header}")
    endif()
  endforeach()
endforeach()
if(missing)
  string(REPLACE ";" "\n  " missing "${missing}")
  message(FATAL_ERROR "public headers not included by <tracegraph/tracegraph.h> (add them there "
                      "or to the layer's All.h):\n  ${missing}")
endif()
list(LENGTH included count)
message(STATUS "umbrella reaches all ${count} public headers")

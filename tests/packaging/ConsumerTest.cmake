# CTest script of packaging.consumer: installs the build tree into a scratch prefix, then
# configures, builds and runs tests/packaging/consumer against it with find_package.
#
# cmake -DBUILD_DIR=<build> -DCONFIG=<cfg> -DWORK_DIR=<scratch> -DCONSUMER_DIR=<source>
#       -DGENERATOR=<generator> -DCXX_COMPILER=<c++> [-DCXX_FLAGS=<flags>] -P ConsumerTest.cmake
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} failed (${code})\nstdout: ${out}\nstderr: ${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --config "${CONFIG}"
    --prefix "${prefix}")
foreach(file include/tracegraph/tracegraph.h include/tracegraph/backend/Scene.h
             include/tracegraph/scenegraph/SceneGraph.h include/tracegraph/nodes/Mesh.h
             include/tracegraph/loaders/SceneSource.h bin/tg-render)
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "cmake --install did not install ${file}")
  endif()
endforeach()

# Only the scratch prefix is searched for Tracegraph, so the build tree cannot stand in for it.
run("configuring the consumer" "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build"
    -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=${CONFIG} "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_PREFIX_PATH=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building the consumer" "${CMAKE_COMMAND}" --build "${WORK_DIR}/build" --config "${CONFIG}")
find_program(consumer consumer PATHS "${WORK_DIR}/build" "${WORK_DIR}/build/${CONFIG}"
             NO_DEFAULT_PATH REQUIRED)
run("running the consumer" "${consumer}")
if(NOT output MATCHES "^OK")
  message(FATAL_ERROR "the consumer printed: ${output}")
endif()
message(STATUS "${output}")

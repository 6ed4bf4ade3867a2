# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the built libshadow into a scratch prefix, then configures, builds and runs
# a downstream project (SOURCE_DIR: tests/downstream, or examples/testing-downstream) against it
# with find_package(libshadow). RUN: the executable to run in its build folder (default
# `downstream`). CHECK_COMPONENTS: also check find_package's component handling.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --component Unspecified)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -G ${CMAKE_GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
if(NOT RUN)
  set(RUN downstream)
endif()
if(CHECK_COMPONENTS)
  # Components: `testing` is found; an unknown one fails find_package cleanly with REQUIRED
  # (an error naming it) and is only reported missing when optional.
  set(probe ${WORK_DIR}/components)
  file(WRITE ${probe}/required/CMakeLists.txt
    "cmake_minimum_required(VERSION 3.22)\nproject(p LANGUAGES NONE)\n"
    "find_package(libshadow REQUIRED COMPONENTS testing no_such_component)\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${probe}/required -B ${probe}/required/build
                          -DCMAKE_PREFIX_PATH=${prefix}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "component 'no_such_component' is not installed")
    message(FATAL_ERROR "find_package(libshadow REQUIRED COMPONENTS no_such_component) did not fail cleanly (${rc}):\n${out}\n${err}")
  endif()
  file(WRITE ${probe}/optional/CMakeLists.txt
    "cmake_minimum_required(VERSION 3.22)\nproject(p LANGUAGES NONE)\n"
    "find_package(libshadow REQUIRED COMPONENTS testing OPTIONAL_COMPONENTS no_such_component)\n"
    "message(STATUS \"found=\${libshadow_FOUND} testing=\${libshadow_testing_FOUND} other=\${libshadow_no_such_component_FOUND}\")\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${probe}/optional -B ${probe}/optional/build
                          -DCMAKE_PREFIX_PATH=${prefix}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "found=1 testing=TRUE other=FALSE")
    message(FATAL_ERROR "optional components misreported (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "components: testing found; a missing required component fails cleanly")
endif()
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/lib:${prefix}/lib64 ${WORK_DIR}/build/${RUN})

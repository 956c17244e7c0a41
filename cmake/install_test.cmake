# CTest's install_example (top CMakeLists.txt), run with cmake -P: installs the build tree BUILD_DIR (configuration
# CONFIG) into WORK_DIR/prefix, builds the example EXAMPLE_DIR against it with find_package(TripSitter), with the
# build tree's compiler, launcher and CMAKE_CXX_FLAGS (CXX_COMPILER, CXX_COMPILER_LAUNCHER, CXX_FLAGS), and runs it.
cmake_minimum_required(VERSION 3.25)

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --config ${CONFIG} --prefix ${WORK_DIR}/prefix)
step("configuring the example"
     ${CMAKE_COMMAND} -S ${EXAMPLE_DIR} -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
     -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
     -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_COMPILER_LAUNCHER} "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
step("building the example" ${CMAKE_COMMAND} --build ${WORK_DIR}/build --config ${CONFIG})
step("running the example" ${WORK_DIR}/build/device_bench)
message(STATUS "device_bench printed: ${output}")
# The demo scene puts a sphere at the centre of the screen: a frame was shown and its centre is not background.
if(NOT output MATCHES "^demo 640x480: centre pixel 0x[0-9a-f][0-9a-f][0-9a-f], crc32 [0-9a-f]+\n$")
  message(FATAL_ERROR "unexpected output from device_bench")
endif()
if(output MATCHES "centre pixel 0x036")
  message(FATAL_ERROR "the centre pixel is the background")
endif()
file(REMOVE_RECURSE ${WORK_DIR})

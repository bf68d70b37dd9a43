# ctest consumer_test (tests/CMakeLists.txt): installs the build tree into a
# temporary prefix, builds tests/consumer against it with
# find_package(clothfit) and runs it.
#   cmake -DBUILD_DIR=.. -DWORK_DIR=.. -DSOURCE_DIR=.. -DCONFORMANCE=..
#         -DGENERATOR=.. -P run_consumer.cmake
foreach(var BUILD_DIR WORK_DIR SOURCE_DIR CONFORMANCE GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: ${var} is not set")
  endif()
endforeach()

include(${CMAKE_CURRENT_LIST_DIR}/consumer_steps.cmake)
install_and_build_consumer(${BUILD_DIR} ${WORK_DIR} ${SOURCE_DIR} ${GENERATOR})
set(prefix ${WORK_DIR}/prefix)
run(${WORK_DIR}/build/consumer ${CONFORMANCE}
    ${SOURCE_DIR}/fitted_lafortune.json)
# The header-only component needs GLM alone.
file(WRITE ${WORK_DIR}/models_only/CMakeLists.txt
  "cmake_minimum_required(VERSION 3.18)\n"
  "project(models_only LANGUAGES CXX)\n"
  "find_package(clothfit REQUIRED COMPONENTS models)\n"
  "if(TARGET clothfit::fitting)\n"
  "  message(FATAL_ERROR \"COMPONENTS models loaded every library\")\n"
  "endif()\n"
  "if(NOT TARGET clothfit::models)\n"
  "  message(FATAL_ERROR \"no clothfit::models\")\n"
  "endif()\n")
run(${CMAKE_COMMAND} -S ${WORK_DIR}/models_only -B ${WORK_DIR}/models_only/b
    -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix})
# The CLI is installed and runs.
run(${prefix}/bin/clothfit presets)

# ctest consumer_api_test (tests/CMakeLists.txt): installs the build tree
# into a temporary prefix, builds tests/consumer_api against it with
# find_package(clothfit COMPONENTS api), runs it, and checks with ldd that
# the executable needs none of the solver's or the image libraries' shared
# libraries.
#   cmake -DBUILD_DIR=.. -DWORK_DIR=.. -DSOURCE_DIR=.. -DFITTED=..
#         -DGENERATOR=.. -P run_api_consumer.cmake
foreach(var BUILD_DIR WORK_DIR SOURCE_DIR FITTED GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_api_consumer.cmake: ${var} is not set")
  endif()
endforeach()

include(${CMAKE_CURRENT_LIST_DIR}/../consumer/consumer_steps.cmake)
install_and_build_consumer(${BUILD_DIR} ${WORK_DIR} ${SOURCE_DIR} ${GENERATOR})
run(${WORK_DIR}/build/renderer ${FITTED} ${WORK_DIR})

# The documents the README and the help cite are installed beside them.
foreach(doc README.md docs/formats.md docs/models.md docs/cli.md
            docs/renderer.md)
  if(NOT EXISTS ${WORK_DIR}/prefix/share/doc/clothfit/${doc})
    message(FATAL_ERROR "not installed: share/doc/clothfit/${doc}")
  endif()
endforeach()

execute_process(COMMAND ldd ${WORK_DIR}/build/renderer
  OUTPUT_VARIABLE libraries RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ldd failed (${rc})")
endif()
foreach(forbidden ceres opencv OpenImageIO glog gflags lapack blas cholmod
                  metis)
  string(TOLOWER "${libraries}" lower)
  string(TOLOWER "${forbidden}" name)
  if(lower MATCHES "lib${name}")
    message(FATAL_ERROR "the api consumer needs lib${forbidden}:\n${libraries}")
  endif()
endforeach()
message(STATUS "api consumer's shared libraries:\n${libraries}")

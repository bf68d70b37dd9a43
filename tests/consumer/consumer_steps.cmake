# The steps the consumer tests share (run_consumer.cmake,
# ../consumer_api/run_api_consumer.cmake): run a command or fail, and
# install the build tree into WORK_DIR/prefix, then configure and build the
# consumer project SOURCE_DIR against it in WORK_DIR/build.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()

function(install_and_build_consumer build_dir work_dir source_dir generator)
  file(REMOVE_RECURSE ${work_dir})
  run(${CMAKE_COMMAND} --install ${build_dir} --prefix ${work_dir}/prefix)
  run(${CMAKE_COMMAND} -S ${source_dir} -B ${work_dir}/build -G ${generator}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${work_dir}/prefix)
  run(${CMAKE_COMMAND} --build ${work_dir}/build)
endfunction()

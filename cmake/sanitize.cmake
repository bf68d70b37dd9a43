# Sanitizer and fuzzing builds (docs/reliability.md). Each goes in
# its own build directory:
#   cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
#     -DCLOTHFIT_SANITIZE=ON -DCLOTHFIT_BUILD_BENCHMARKS=OFF
#   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCLOTHFIT_FUZZ=ON \
#     -DCLOTHFIT_BUILD_TESTS=OFF -DCLOTHFIT_BUILD_BENCHMARKS=OFF
# The flags apply to every target of the project (libraries, CLI, tests);
# system libraries (Ceres, OpenCV, OpenImageIO, GoogleTest) stay
# uninstrumented.
option(CLOTHFIT_SANITIZE
       "Build everything with AddressSanitizer + UndefinedBehaviorSanitizer" OFF)
option(CLOTHFIT_FUZZ
       "Build the libFuzzer targets in fuzz/ (needs clang; implies ASan+UBSan)"
       OFF)

set(CLOTHFIT_SANITIZER_FLAGS -fsanitize=address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)

if(CLOTHFIT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "CLOTHFIT_FUZZ needs clang (libFuzzer): configure "
                        "with CC=clang CXX=clang++")
  endif()
  # Libraries get the coverage instrumentation; the fuzz executables add
  # -fsanitize=fuzzer (libFuzzer's main) in fuzz/CMakeLists.txt.
  add_compile_options(${CLOTHFIT_SANITIZER_FLAGS} -fsanitize=fuzzer-no-link)
  add_link_options(${CLOTHFIT_SANITIZER_FLAGS})
elseif(CLOTHFIT_SANITIZE)
  add_compile_options(${CLOTHFIT_SANITIZER_FLAGS})
  add_link_options(${CLOTHFIT_SANITIZER_FLAGS})
endif()

# Sanitizer and fuzzer builds (docs/testing.md, "Sanitizers", "Fuzzing"):
#   SEMLOC_SANITIZE=ON       everything (library, tools, tests, benchmarks) built with
#                            AddressSanitizer + UndefinedBehaviorSanitizer; any UB aborts.
#   SEMLOC_BUILD_FUZZERS=ON  also the libFuzzer targets of tests/fuzz (clang only); the
#                            library's parsing units get libFuzzer's coverage instrumentation.
# tests/sanitize.sh and tests/fuzz/run.sh share one build directory (build-asan) with both on.
option(SEMLOC_SANITIZE "Build with AddressSanitizer + UndefinedBehaviorSanitizer" OFF)
option(SEMLOC_BUILD_FUZZERS "Build the libFuzzer targets of tests/fuzz (clang; sanitized)" OFF)

if(SEMLOC_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SEMLOC_BUILD_FUZZERS needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ (Debian: apt-get install clang libclang-rt-14-dev)")
  endif()
  set(SEMLOC_SANITIZE ON CACHE BOOL "" FORCE)
endif()

# The flags a sanitized build compiles and links with; tests/check_embed_example.cmake
# passes them on to the example it builds against the installed (sanitized) library.
set(SEMLOC_SANITIZER_FLAGS "")
if(SEMLOC_SANITIZE)
  set(SEMLOC_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined
                             -fno-omit-frame-pointer)
  add_compile_options(${SEMLOC_SANITIZER_FLAGS})
  add_link_options(${SEMLOC_SANITIZER_FLAGS})
endif()

# Builds examples/embed against an *installed* semloc and runs it: install the build tree
# into a scratch prefix, configure the example with find_package(semloc), build, run.
# Inputs: BUILD_DIR (semloc's build tree), SRC_DIR, OUT_DIR, CXX_COMPILER, CXX_FLAGS (may be
# empty; a sanitized tree's flags).
file(REMOVE_RECURSE ${OUT_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${OUT_DIR}/install
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed: ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC_DIR}/examples/embed -B ${OUT_DIR}/build
                        -DCMAKE_PREFIX_PATH=${OUT_DIR}/install -DCMAKE_BUILD_TYPE=Release
                        -DCMAKE_CXX_COMPILER=${CXX_COMPILER} "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
                        "-DCMAKE_EXE_LINKER_FLAGS=${CXX_FLAGS}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the example against the installed tree failed:\n${out}${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${OUT_DIR}/build
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the example failed:\n${out}${err}")
endif()
execute_process(COMMAND ${OUT_DIR}/build/robot_loop
                        ${OUT_DIR}/install/share/semloc/maps/paper_50x50.yaml
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the example did not localize (exit ${rc}):\n${out}${err}")
endif()
# A robot links the core alone: the example needs libsemloc, not libsemloc_tools.
execute_process(COMMAND ldd ${OUT_DIR}/build/robot_loop OUTPUT_VARIABLE libs RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT libs MATCHES "libsemloc\\.so" OR libs MATCHES "libsemloc_tools")
  message(FATAL_ERROR "the example must link libsemloc alone; ldd says:\n${libs}")
endif()
# The active example: the policy drives until the particles converge, then the mission.
execute_process(COMMAND ${OUT_DIR}/build/active_loop
                        ${OUT_DIR}/install/share/semloc/maps/paper_50x50.yaml
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "converged: back to the mission")
  message(FATAL_ERROR "the active example did not converge (exit ${rc}):\n${out}${err}")
endif()

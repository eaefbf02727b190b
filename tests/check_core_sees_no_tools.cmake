# The libraries' direction: a source on the core's include path (libsemloc/include and
# libsemloc/src, as every core source) compiles with a core header and does not with a header
# of libsemloc_tools. Inputs: BUILD_DIR (the build tree holding the probe targets).
function(build_probe target result output)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${target}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${result} ${rc} PARENT_SCOPE)
  set(${output} "${out}${err}" PARENT_SCOPE)
endfunction()

build_probe(core_include_probe_core rc out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the probe does not compile even with a core header:\n${out}")
endif()
build_probe(core_include_probe_tools rc out)
if(rc EQUAL 0)
  message(FATAL_ERROR "a core source could include a tools header (semloc/simulator/Simulator.h)")
endif()
if(NOT out MATCHES "semloc/simulator/Simulator\\.h")
  message(FATAL_ERROR "the probe with a tools header failed for another reason:\n${out}")
endif()
message(STATUS "core sources see core headers, not the tools' headers")

# Runs semloc-simulate end to end: outputs exist, nothing temporary is left, the effective
# ini reproduces the rawlog byte for byte, and another seed gives another rawlog.
# Inputs: APP, INI, OUT_DIR. Leaves ${OUT_DIR}/sim_app.rawlog for the rawlog-edit test.
set(out ${OUT_DIR}/sim_app)
file(REMOVE ${out}.rawlog ${out}_gt.txt ${out}.ini ${out}_rerun.rawlog ${out}_seed8.rawlog)

function(run_app)
  execute_process(COMMAND ${APP} ${ARGN} OUTPUT_VARIABLE o ERROR_VARIABLE e RESULT_VARIABLE rc)
  message(STATUS "semloc-simulate ${ARGN}:\n${o}${e}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "semloc-simulate ${ARGN} failed (${rc})")
  endif()
endfunction()

run_app(${INI} -o ${out}.rawlog --seed 7)
foreach(f ${out}.rawlog ${out}_gt.txt ${out}.ini)
  if(NOT EXISTS ${f})
    message(FATAL_ERROR "missing output ${f}")
  endif()
endforeach()
file(GLOB tmps ${OUT_DIR}/sim_app*.tmp)
if(tmps)
  message(FATAL_ERROR "temporary files left behind: ${tmps}")
endif()

run_app(${out}.ini -o ${out}_rerun.rawlog)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${out}.rawlog ${out}_rerun.rawlog
                RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "rerunning the effective ini ${out}.ini did not reproduce the rawlog")
endif()

run_app(${INI} -o ${out}_seed8.rawlog --seed 8)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${out}.rawlog ${out}_seed8.rawlog
                RESULT_VARIABLE same)
if(same EQUAL 0)
  message(FATAL_ERROR "seeds 7 and 8 gave the same rawlog")
endif()

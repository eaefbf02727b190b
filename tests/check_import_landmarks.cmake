# semloc-import-landmarks on simul-landmarks' output (written by test_LandmarkImport):
# the outputs exist, the world loads in semloc-plot-world, and a missing input fails
# with a message and no output. Inputs: IMPORT, PLOT, DIR.
set(in ${DIR}/OUT/lm.rawlog)
file(REMOVE ${DIR}/conv.rawlog ${DIR}/conv_world.yaml ${DIR}/conv_gt.txt)
execute_process(COMMAND ${IMPORT} ${in} -o ${DIR}/conv.rawlog --label buoy
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "import failed (${rc}): ${out}${err}")
endif()
foreach(f conv.rawlog conv_world.yaml conv_gt.txt)
  if(NOT EXISTS ${DIR}/${f})
    message(FATAL_ERROR "missing output ${f}")
  endif()
endforeach()
execute_process(COMMAND ${PLOT} ${DIR}/conv_world.yaml -o ${DIR}/conv_world.png RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the imported world does not load")
endif()
execute_process(COMMAND ${IMPORT} ${DIR}/OUT/nope.rawlog -o ${DIR}/nope.rawlog
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "nope.rawlog" OR EXISTS ${DIR}/nope.rawlog)
  message(FATAL_ERROR "a missing input must fail naming it and write nothing: ${rc} ${err}")
endif()

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
# semloc-localize runs on the imported dataset directly.
if(LOCALIZE AND SEMANTIC_INI)
  file(WRITE ${DIR}/conv.ini
       "base = ${SEMANTIC_INI}\n[LocalizationExperiment]\nmap_file = conv_world.yaml\n"
       "ground_truth_path_file = conv_gt.txt\nlogOutput_dir = conv_out\nparticles_count = 3000\n")
  file(REMOVE_RECURSE ${DIR}/conv_out)
  execute_process(COMMAND ${LOCALIZE} conv.ini conv.rawlog -q WORKING_DIRECTORY ${DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${DIR}/conv_out/summary.yaml)
    message(FATAL_ERROR "semloc-localize failed on the imported dataset (${rc}): ${out}${err}")
  endif()
  file(READ ${DIR}/conv_out/summary.yaml summary)
  if(NOT summary MATCHES "observations_used: [1-9]")
    message(FATAL_ERROR "no imported observation was used:\n${summary}")
  endif()
endif()

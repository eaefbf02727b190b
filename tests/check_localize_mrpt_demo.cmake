# MRPT's own pf-localization demo (/usr/share/mrpt/config_files/pf-localization/
# localization_demo.ini: occupancy grid from a .simplemap, likelihood field, KLD sampling,
# 40000 particles) must run unchanged through semloc-localize and end where MRPT's stock
# pf-localization ends: (15.91, -10.01) m, measured on its own run of the same files.
# Usage: cmake -DAPP=... -DINI=... -DOUT_DIR=... -P check_localize_mrpt_demo.cmake
set(out ${OUT_DIR}/mrpt_localization_demo)
file(REMOVE_RECURSE ${out})
execute_process(COMMAND ${APP} ${INI} -o ${out} -q RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "semloc-localize failed on ${INI}: ${err}")
endif()
foreach(f steps.csv summary.yaml config.ini)
  if(NOT EXISTS ${out}/${f})
    message(FATAL_ERROR "missing ${out}/${f}")
  endif()
endforeach()
file(STRINGS ${out}/steps.csv rows)
list(LENGTH rows n)
if(NOT n EQUAL 38)
  message(FATAL_ERROR "expected 37 steps (+ header) in steps.csv, got ${n} lines")
endif()
list(GET rows -1 last)
# est_x, est_y are the 6th and 7th columns (the ground-truth columns are empty here).
if(NOT last MATCHES "^[0-9]+,[^,]*,[^,]*,[^,]*,[^,]*,([^,]+),([^,]+),")
  message(FATAL_ERROR "unexpected steps.csv row: ${last}")
endif()
set(x ${CMAKE_MATCH_1})
set(y ${CMAKE_MATCH_2})
if(x LESS 15.81 OR x GREATER 16.01 OR y LESS -10.11 OR y GREATER -9.91)
  message(FATAL_ERROR "final estimate (${x}, ${y}) is not within 0.1 m of pf-localization's "
                      "(15.91, -10.01)")
endif()
file(READ ${out}/summary.yaml summary)
if(NOT summary MATCHES "variant: \"grid_lf\"")
  message(FATAL_ERROR "unexpected variant in ${out}/summary.yaml")
endif()
message(STATUS "localization_demo.ini: final estimate (${x}, ${y})")

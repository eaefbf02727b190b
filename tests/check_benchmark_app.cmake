# Runs semloc-benchmark on a small experiment (3 runs x semantic + geometric, a short
# trajectory, few particles): every output exists with its columns, the figures are PNGs,
# results do not depend on `jobs`, and bad configurations fail clearly leaving no output.
# Inputs: APP, CONFIG_DIR (the repository's config/localize/), SIMULATE_INI, OUT_DIR.
cmake_policy(SET CMP0007 NEW)  # keep the empty cells of CSV rows
set(dir ${OUT_DIR}/benchmark_app)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

function(write_ini name jobs extra)
  file(WRITE ${dir}/${name}.ini
       "[Benchmark]\nruns = 3\nvariants = ${CONFIG_DIR}/semantic.ini, geometric.ini\n"
       "simulate_ini = ${SIMULATE_INI}\noutput_dir = ${dir}/${name}_out\n"
       "jobs = ${jobs}\nmax_steps = 30\nparticles = 300  // few, fast\n${extra}")
  # `geometric.ini` is resolved next to the benchmark ini (a copy, its base the shipped one).
  file(READ ${CONFIG_DIR}/geometric.ini g)
  string(REPLACE "\nbase = filter.ini\n" "\nbase = ${CONFIG_DIR}/filter.ini\n" g "${g}")
  file(WRITE ${dir}/geometric.ini "${g}")
endfunction()

function(run_app name expect_ok)
  # A run that hangs is ended after 300 s (a few seconds is the norm), its output printed.
  execute_process(COMMAND ${APP} ${dir}/${name}.ini OUTPUT_VARIABLE o ERROR_VARIABLE e
                  RESULT_VARIABLE rc TIMEOUT 300)
  message(STATUS "semloc-benchmark ${name}.ini (${rc}):\n${o}${e}")
  set(out "${o}${e}" PARENT_SCOPE)
  if(expect_ok AND NOT rc EQUAL 0)
    message(FATAL_ERROR "semloc-benchmark ${name}.ini failed (${rc})")
  endif()
  if(NOT expect_ok AND rc EQUAL 0)
    message(FATAL_ERROR "semloc-benchmark ${name}.ini should have failed")
  endif()
endfunction()

function(check_header file expected)
  file(STRINGS ${file} lines LIMIT_COUNT 1)
  if(NOT lines STREQUAL "${expected}")
    message(FATAL_ERROR "${file}: header\n  ${lines}\nexpected\n  ${expected}")
  endif()
endfunction()

function(check_png file)
  if(NOT EXISTS ${file})
    message(FATAL_ERROR "missing figure ${file}")
  endif()
  file(READ ${file} head LIMIT 16 HEX)
  # PNG signature, then the first chunk's length (13) and type IHDR.
  if(NOT head STREQUAL "89504e470d0a1a0a0000000d49484452")
    message(FATAL_ERROR "${file} is not a PNG (starts ${head})")
  endif()
endfunction()

# Results without the timing columns (total_update_s, mean_update_us_per_particle, wall_time_s).
function(results_without_timing file var)
  file(STRINGS ${file} lines)
  set(kept "")
  foreach(l ${lines})
    string(REPLACE "," ";" cols "${l}")
    list(REMOVE_AT cols 13 14 17)
    list(APPEND kept "${cols}")
  endforeach()
  set(${var} "${kept}" PARENT_SCOPE)
endfunction()

write_ini(jobs1 1 "")
write_ini(jobs2 2 "")
run_app(jobs1 TRUE)
if(NOT out MATCHES "\\| semantic \\| 3 \\|" OR NOT out MATCHES "\\| geometric \\| 3 \\|")
  message(FATAL_ERROR "the table was not printed")
endif()
run_app(jobs2 TRUE)

set(o1 ${dir}/jobs1_out)
foreach(f results.csv curves.csv report.md figures.gp)
  if(NOT EXISTS ${o1}/${f})
    message(FATAL_ERROR "missing output ${o1}/${f}")
  endif()
endforeach()
check_header(${o1}/results.csv
  "run,seed,variant,particles,threads,steps,steps_with_ground_truth,converged,convergence_step,convergence_time_s,mean_err_after_conv_m,rmse_m,final_err_m,total_update_s,mean_update_us_per_particle,final_particles,reinitializations,wall_time_s,kidnap_step,recovery_steps,nees_median,nees_inside_share,nees_mean_well_conditioned,nees_well_conditioned_share,control,distance_to_convergence_m")
check_header(${o1}/curves.csv
  "variant,step,t_s,runs,err_xy_mean,err_xy_p10,err_xy_p50,err_xy_p90,var_xy_mean,var_xy_p10,var_xy_p50,var_xy_p90")
file(STRINGS ${o1}/results.csv rows)
list(LENGTH rows n)
if(NOT n EQUAL 7)
  message(FATAL_ERROR "results.csv: ${n} lines, expected a header and 3 runs x 2 variants")
endif()
file(STRINGS ${o1}/curves.csv rows)
list(LENGTH rows n)
if(NOT n EQUAL 61)
  message(FATAL_ERROR "curves.csv: ${n} lines, expected a header and 2 variants x 30 steps")
endif()
file(READ ${o1}/report.md report)
foreach(s "1171934146" "6977878010" "| semantic |" "| geometric |"
          "detector bound after conv. [m]" "| median NEES | NEES inside 95 % [%] | mean NEES, well-conditioned steps | well-conditioned steps [%] |")
  string(FIND "${report}" "${s}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "report.md lacks '${s}'")
  endif()
endforeach()
foreach(f fig_variance.png fig_error.png world_paths.png)
  check_png(${o1}/${f})
endforeach()
file(GLOB staging ${dir}/.*staging*)
if(staging OR EXISTS ${o1}/runs)
  message(FATAL_ERROR "temporary files left behind: ${staging}")
endif()

results_without_timing(${o1}/results.csv r1)
results_without_timing(${dir}/jobs2_out/results.csv r2)
if(NOT r1 STREQUAL r2)
  message(FATAL_ERROR "results differ between jobs = 1 and jobs = 2:\n${r1}\n${r2}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${o1}/curves.csv
                        ${dir}/jobs2_out/curves.csv RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "curves.csv differs between jobs = 1 and jobs = 2")
endif()

# Bad configurations: a clear error naming the key, nothing written.
foreach(case "unknown_key|runz = 3|\\[Benchmark\\] runz"
             "bad_value|filter_threads = two|\\[Benchmark\\] filter_threads"
             "missing_variant|variants = semantic_typo|\\[Benchmark\\] variants: 'semantic_typo.ini' does not exist")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 name)
  list(GET parts 1 line)
  list(GET parts 2 pattern)
  write_ini(${name} 1 "")
  file(READ ${dir}/${name}.ini text)
  if(line MATCHES "^variants")
    string(REGEX REPLACE "variants = [^\n]*" "${line}" text "${text}")
    file(WRITE ${dir}/${name}.ini "${text}")
  else()
    file(APPEND ${dir}/${name}.ini "${line}\n")
  endif()
  run_app(${name} FALSE)
  if(NOT out MATCHES "semloc-benchmark: .*${pattern}")
    message(FATAL_ERROR "${name}: the error does not match '${pattern}':\n${out}")
  endif()
  if(EXISTS ${dir}/${name}_out)
    message(FATAL_ERROR "${name}: ${dir}/${name}_out was created")
  endif()
endforeach()

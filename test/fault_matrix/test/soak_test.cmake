# A short soak (ctest fault_matrix_soak): `cobra soak` runs for 20 s, writes its CSV (a row per run
# with the process's resident memory and open descriptors) and ends with its summary line; the
# descriptors stay constant from the first run to the last (exit status 0 says so).
execute_process(COMMAND ${COBRA} soak --duration 20 --seed 3 --report ${REPORT}
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "cobra soak exited with ${status}")
endif()
if(NOT out MATCHES "soak: [1-9][0-9]* runs in [0-9.]+ s .*open file descriptors ([0-9]+) after the first run, ([0-9]+) after the last \\(max [0-9]+\\): constant")
  message(FATAL_ERROR "cobra soak: no summary line saying the descriptors stayed constant")
endif()
if(NOT out MATCHES "kB once every task had run \\(run [1-9][0-9]*\\), at most [0-9]+ kB after it")
  message(FATAL_ERROR "cobra soak: the summary line does not give the memory from the run after which every task had run")
endif()
file(STRINGS ${REPORT} rows)
list(LENGTH rows n)
list(GET rows 0 header)
if(NOT header STREQUAL "wall [s],run,task,scenario,cell,outcome,verdict,VmRSS [kB],open fds" OR n LESS 2)
  message(FATAL_ERROR "cobra soak: ${REPORT} is not a CSV of runs: ${header} (${n} lines)")
endif()

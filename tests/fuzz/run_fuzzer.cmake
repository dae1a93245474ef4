# run_fuzzer.cmake: runs one libFuzzer harness for SECONDS from its seed folders, as CTest's
# fuzz_<harness> test: `cmake -DFUZZER=... -DSECONDS=... -DCORPUS=DIR[:DIR...] -DDICT=... -DWORK=... -P run_fuzzer.cmake`.
# New inputs go to WORK/corpus (never into the repository), a failing input to WORK/ (its path is
# printed); any crash, abort, sanitizer report, uncaught exception or 10 s hang fails the test.
file(MAKE_DIRECTORY ${WORK}/corpus)
set(options -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=${WORK}/)
if(DICT)
  list(APPEND options -dict=${DICT})
endif()
string(REPLACE ":" ";" seeds "${CORPUS}")
execute_process(COMMAND ${FUZZER} ${options} ${WORK}/corpus ${seeds} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${FUZZER} found a failing input (exit ${status}); it is saved in ${WORK}/ "
                      "(replay it: ${FUZZER} ${WORK}/<crash, leak or timeout>-...)")
endif()

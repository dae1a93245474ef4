# check_quick_golden.cmake: runs scripts/quick.lua and compares its tables, report and CSVs with
# the ones kept in tests/golden/quick (wall-clock columns aside). A change of the engine that
# changes results fails here; when the change is meant, regenerate the golden files with
#   roger run scripts/quick.lua --out DIR && cp DIR/{tables.md,report.json,summary.csv} tests/golden/quick/
# (and each DIR/trials/*/*/*/curve.csv), and say why in the commit.
# Run by CTest as `cmake -DROGER=... -DSOURCE=... -DOUT=... [-DEXTRA=--no-eval-cache] -P check_quick_golden.cmake`.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ROGER} run scripts/quick.lua --out ${OUT} ${EXTRA}
                WORKING_DIRECTORY ${SOURCE} RESULT_VARIABLE run_status OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT run_status EQUAL 0)
  message(FATAL_ERROR "roger run scripts/quick.lua failed (${run_status}):\n${log}")
endif()
execute_process(COMMAND bash ${SOURCE}/tests/tools/compare_results.sh --golden ${SOURCE}/tests/golden/quick ${OUT}
                RESULT_VARIABLE cmp_status OUTPUT_VARIABLE cmp ERROR_VARIABLE cmp)
if(NOT cmp_status EQUAL 0)
  message(FATAL_ERROR "scripts/quick.lua no longer gives the kept results:\n${cmp}")
endif()
message(STATUS "${cmp}")

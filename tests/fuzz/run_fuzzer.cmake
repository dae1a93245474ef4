# run_fuzzer.cmake: runs one libFuzzer harness for SECONDS from its seed folders, as CTest's
# fuzz_<harness> test: `cmake -DFUZZER=... -DSECONDS=... -DCORPUS=DIR[:DIR...] -DDICT=... -DWORK=... -P run_fuzzer.cmake`.
# New inputs go to WORK/corpus (never into the repository), a failing input to WORK/ (its path is
# printed); any crash, abort, sanitizer report, uncaught exception or 10 s hang fails the test.
#
# The fuzzer's own output goes to WORK/fuzzer.log. On a failure its cause (the harness's or the
# sanitizer's words, the first frames of the stack) and the failing input's bytes are printed last:
# a CI log cut in the middle (a fuzzer prints a line per new input) still ends with them.
file(MAKE_DIRECTORY ${WORK}/corpus)
file(GLOB previous ${WORK}/crash-* ${WORK}/leak-* ${WORK}/timeout-* ${WORK}/oom-*)
if(previous)
  file(REMOVE ${previous})  # a failing input of an earlier run is not this run's
endif()
set(options -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=${WORK}/)
if(DICT)
  list(APPEND options -dict=${DICT})
endif()
string(REPLACE ":" ";" seeds "${CORPUS}")
set(log ${WORK}/fuzzer.log)
execute_process(COMMAND ${FUZZER} ${options} ${WORK}/corpus ${seeds} RESULT_VARIABLE status OUTPUT_FILE ${log}
                ERROR_FILE ${log})
if(status EQUAL 0)
  file(STRINGS ${log} stats REGEX "^(Done|stat::number_of_executed_units)")
  message(STATUS "${FUZZER}: nothing found (${stats})")
  return()
endif()
# Why it failed: the lines that say so, and the frames of the stack that are the project's.
file(STRINGS ${log} cause REGEX "(not a roger::Error|terminate called|what\\(\\)|ERROR:|SUMMARY:|runtime error|Assertion|#[0-9]+ .* in [^ ]*(roger|LLVMFuzzerTestOneInput))")
list(JOIN cause "\n  " cause)  # indented: CMake reflows a message's plain paragraphs, not these
file(GLOB inputs ${WORK}/crash-* ${WORK}/leak-* ${WORK}/timeout-* ${WORK}/oom-*)
set(shown "")
foreach(input ${inputs})
  file(SIZE ${input} size)
  file(READ ${input} hex LIMIT 2000 HEX)
  string(LENGTH "${hex}" hex_length)
  # Printable ASCII as itself, every other byte as \xHH: the input is readable in the log and exact.
  set(text "")
  if(hex_length GREATER 0)
    math(EXPR last "${hex_length} - 2")
    foreach(at RANGE 0 ${last} 2)
      string(SUBSTRING "${hex}" ${at} 2 byte)
      math(EXPR code "0x${byte}")
      if(code GREATER_EQUAL 32 AND code LESS 127 AND NOT code EQUAL 92)
        string(ASCII ${code} char)
        string(APPEND text "${char}")
      else()
        string(APPEND text "\\x${byte}")
      endif()
    endforeach()
  endif()
  string(APPEND shown "\n${input} (${size} bytes; the first 2000, bytes outside printable ASCII as \\xHH):\n  ${text}\n")
endforeach()
message(FATAL_ERROR "${FUZZER} found a failing input (exit ${status}); the fuzzer's output is ${log}.\n"
                    "Cause:\n  ${cause}\n${shown}\n"
                    "Replay it: ${FUZZER} ${WORK}/<crash, leak or timeout>-...")

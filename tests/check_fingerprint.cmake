# tests/check_fingerprint.cmake: the engine's fingerprint (engine/fingerprint.cmake), which a results
# folder's manifest records, covers what a trial runs and nothing else. MODULES, found from the link
# graph by engine/batch/CMakeLists.txt, holds batch and the modules it links, and none of the
# command line's, pictures', report's, propose's or Python's folders; on a copy, an edit in a folder
# outside MODULES leaves the value and one inside changes it. Run with -DMODULES=... -DFINGERPRINT=...
# -DWORK=<scratch folder> (tests/CMakeLists.txt).
cmake_policy(SET CMP0057 NEW)  # if(IN_LIST) in script mode
string(REPLACE "," ";" modules "${MODULES}")
foreach(module batch core senses sim perception control learn teach script)
  if(NOT module IN_LIST modules)
    message(FATAL_ERROR "the fingerprint leaves out ${module}, which trials run (MODULES: ${MODULES})")
  endif()
endforeach()
foreach(module cli view report propose python)
  if(module IN_LIST modules)
    message(FATAL_ERROR "the fingerprint covers ${module}, which no trial runs (MODULES: ${MODULES})")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK})
file(WRITE ${WORK}/core/a.cpp "int a;\n")
file(WRITE ${WORK}/core/a.h "extern int a;\n")
file(WRITE ${WORK}/cli/b.cpp "int b;\n")
function(fingerprint out)
  execute_process(COMMAND ${CMAKE_COMMAND} -DENGINE_DIR=${WORK} -DMODULES=core -DOUT=${WORK}/fingerprint.h
                          -P ${FINGERPRINT} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "engine/fingerprint.cmake failed: ${status}")
  endif()
  file(READ ${WORK}/fingerprint.h text)
  set(${out} "${text}" PARENT_SCOPE)
endfunction()
fingerprint(first)
if(NOT first MATCHES "ROGER_ENGINE_FINGERPRINT \"[0-9a-f]+\"")
  message(FATAL_ERROR "no fingerprint written: ${first}")
endif()
file(WRITE ${WORK}/cli/b.cpp "int b;  // a comment of the command line's\n")
fingerprint(second)
if(NOT first STREQUAL second)
  message(FATAL_ERROR "an edit outside MODULES changed the fingerprint")
endif()
file(WRITE ${WORK}/core/a.h "extern int a;  // a comment of a trial's module\n")
fingerprint(third)
if(first STREQUAL third)
  message(FATAL_ERROR "an edit of a module in MODULES left the fingerprint")
endif()
file(REMOVE_RECURSE ${WORK})
message(STATUS "the fingerprint covers ${MODULES}")

# Runs a command and checks its exit code and the text it printed (CTest helper).
# cmake -DCOMMAND="prog|arg|..." -DEXIT_CODE=N [-DMATCH=regex] [-DEXISTS=file] -P ExpectExit.cmake
# (arguments separated by '|', since ';' does not survive being passed through add_test)
string(REPLACE "|" ";" command "${COMMAND}")
execute_process(COMMAND ${command} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL EXIT_CODE)
  message(FATAL_ERROR "exit code ${code}, expected ${EXIT_CODE}\nstdout: ${out}\nstderr: ${err}")
endif()
if(DEFINED MATCH AND NOT "${out}${err}" MATCHES "${MATCH}")
  message(FATAL_ERROR "output does not match '${MATCH}'\nstdout: ${out}\nstderr: ${err}")
endif()
if(DEFINED EXISTS AND NOT EXISTS "${EXISTS}")
  message(FATAL_ERROR "${EXISTS} was not written")
endif()

# cmake -DEXPECT_OUTPUT=<regex> [-DEXPECT_STATUS=1] -P ExpectFailure.cmake -- <command> [args...]
# A program refusing bad input as a user sees it: it must exit with EXPECT_STATUS (1 by
# default; a crash or a signal never passes) and print a message matching EXPECT_OUTPUT,
# which names the file (or option) and the problem. Both streams are searched.
if(NOT DEFINED EXPECT_OUTPUT OR EXPECT_OUTPUT STREQUAL "")
  message(FATAL_ERROR "ExpectFailure.cmake: pass -DEXPECT_OUTPUT=<regex>")
endif()
if(NOT DEFINED EXPECT_STATUS)
  set(EXPECT_STATUS 1)
endif()

set(_command "")
set(_after_separator FALSE)
math(EXPR _last "${CMAKE_ARGC} - 1")
foreach(_i RANGE ${_last})
  if(_after_separator)
    list(APPEND _command "${CMAKE_ARGV${_i}}")
  elseif(CMAKE_ARGV${_i} STREQUAL "--")
    set(_after_separator TRUE)
  endif()
endforeach()
if(NOT _command)
  message(FATAL_ERROR "ExpectFailure.cmake: no command after --")
endif()

execute_process(COMMAND ${_command} RESULT_VARIABLE _status OUTPUT_VARIABLE _out
                ERROR_VARIABLE _err)
string(JOIN " " _shown ${_command})
if(NOT _status STREQUAL "${EXPECT_STATUS}")
  message(FATAL_ERROR "${_shown}\nexited with '${_status}', expected ${EXPECT_STATUS}\n"
                      "stdout:\n${_out}\nstderr:\n${_err}")
endif()
if(NOT "${_out}\n${_err}" MATCHES "${EXPECT_OUTPUT}")
  message(FATAL_ERROR "${_shown}\nexited with ${_status} but printed no message matching "
                      "'${EXPECT_OUTPUT}'\nstdout:\n${_out}\nstderr:\n${_err}")
endif()
message(STATUS "exited with ${_status}: ${_err}")

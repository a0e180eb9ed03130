# Runs a deck checker on one bad deck and judges the result (used by tests/decks/CMakeLists.txt).
#   cmake -DCHECKER="<command>|<arg>|..." -DDECK=<file.inp> -P check_bad_deck.cmake
# Passes only if: the exit status is 1, stderr matches the regex on the deck's first line
# ("** EXPECT: <regex>"), and the output holds no sign of a crash.
if(NOT DEFINED CHECKER OR NOT DEFINED DECK)
  message(FATAL_ERROR "usage: cmake -DCHECKER=<cmd|args> -DDECK=<deck.inp> -P check_bad_deck.cmake")
endif()
string(REPLACE "|" ";" _command "${CHECKER}")

file(STRINGS "${DECK}" _first LIMIT_COUNT 1)
if(NOT _first MATCHES "^\\*\\* EXPECT: (.+)$")
  message(FATAL_ERROR "${DECK}: first line must be '** EXPECT: <regex>'")
endif()
set(_expect "${CMAKE_MATCH_1}")

execute_process(COMMAND ${_command} "${DECK}"
  RESULT_VARIABLE _status OUTPUT_VARIABLE _out ERROR_VARIABLE _err TIMEOUT 50)
message("exit status: ${_status}\n--- stdout:\n${_out}--- stderr:\n${_err}---")

set(_failed "")
if(NOT _status STREQUAL "1")
  string(APPEND _failed "exit status is '${_status}', expected 1. ")
endif()
if(NOT _err MATCHES "${_expect}")
  string(APPEND _failed "stderr does not match the EXPECT regex '${_expect}'. ")
endif()
foreach(_sign "Backtrace" "Error termination" "SIGSEGV" "ERROR STOP")
  string(FIND "${_out}${_err}" "${_sign}" _at)
  if(_at GREATER -1)
    string(APPEND _failed "the output contains '${_sign}'. ")
  endif()
endforeach()
if(_failed)
  message(FATAL_ERROR "${DECK}: ${_failed}")
endif()

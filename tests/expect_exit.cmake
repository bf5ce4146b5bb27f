# Runs COMMAND (a ;-list), checks its exit code is EXPECT_CODE and its output contains
# EXPECT_PATTERN (a regular expression; empty = anything).
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT "${code}" STREQUAL "${EXPECT_CODE}")
  message(FATAL_ERROR "exit code ${code}, expected ${EXPECT_CODE}")
endif()
if(NOT "${EXPECT_PATTERN}" STREQUAL "" AND NOT "${out}${err}" MATCHES "${EXPECT_PATTERN}")
  message(FATAL_ERROR "output does not contain '${EXPECT_PATTERN}'")
endif()

# Runs EXE with ARGS ('|'-separated) and fails unless it exits 1, writes nothing on stdout and
# writes EXPECT (a plain substring) on stderr.
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND ${EXE} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 50)
if(NOT rc STREQUAL "1")
  message(FATAL_ERROR "tocdlab ${args}: exit status '${rc}', expected 1\nstdout: ${out}\nstderr: ${err}")
endif()
if(NOT out STREQUAL "")
  message(FATAL_ERROR "tocdlab ${args}: expected nothing on stdout, got: ${out}")
endif()
string(FIND "${err}" "${EXPECT}" pos)
if(pos EQUAL -1)
  message(FATAL_ERROR "tocdlab ${args}: stderr lacks '${EXPECT}':\n${err}")
endif()

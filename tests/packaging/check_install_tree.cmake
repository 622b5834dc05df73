# Installs BUILD_DIR into PREFIX and fails unless the expected files are there and the
# installed tocdlab reports VERSION.
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}): ${err}")
endif()
set(expected bin/tocdlab share/man/man1/tocdlab.1 share/bash-completion/completions/tocdlab
             share/doc/tocdlab/README.md share/doc/tocdlab/model.md share/tocdlab/examples/lab/real-rig.toml)
if(WITH_GUI)
  list(APPEND expected bin/tocdlab-gui share/man/man1/tocdlab-gui.1)
endif()
foreach(f IN LISTS expected)
  if(NOT EXISTS "${PREFIX}/${f}")
    message(FATAL_ERROR "install tree lacks ${f}")
  endif()
endforeach()
# The man page is help2man's rendering of --help: it has the NAME section and lists commands.
file(READ "${PREFIX}/share/man/man1/tocdlab.1" man)
if(NOT man MATCHES "\\.SH NAME" OR NOT man MATCHES "plot")
  message(FATAL_ERROR "tocdlab.1 is not a man page of tocdlab's --help")
endif()
execute_process(COMMAND ${PREFIX}/bin/tocdlab --version OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^tocdlab ${VERSION}")
  message(FATAL_ERROR "installed tocdlab --version: '${out}' (exit ${rc})")
endif()

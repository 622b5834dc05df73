# Installs BUILD_DIR into PREFIX and fails unless the expected files are there and the
# installed tocdlab reports VERSION.
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}): ${err}")
endif()
set(expected bin/tocdlab share/man/man1/tocdlab.1.gz share/bash-completion/completions/tocdlab
             share/doc/tocdlab/README.md share/doc/tocdlab/docs/model.md share/doc/tocdlab/copyright
             share/doc/tocdlab/changelog.gz share/tocdlab/examples/lab/real-rig.toml)
if(WITH_GUI)
  list(APPEND expected bin/tocdlab-gui share/man/man1/tocdlab-gui.1.gz)
endif()
foreach(f IN LISTS expected)
  if(NOT EXISTS "${PREFIX}/${f}")
    message(FATAL_ERROR "install tree lacks ${f}")
  endif()
endforeach()
# The copyright file is machine-readable (DEP-5) and holds the licence text.
file(READ "${PREFIX}/share/doc/tocdlab/copyright" copyright)
if(NOT copyright MATCHES "^Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/"
   OR NOT copyright MATCHES "GNU AFFERO GENERAL PUBLIC LICENSE")
  message(FATAL_ERROR "share/doc/tocdlab/copyright is not a DEP-5 file with the AGPL text")
endif()
# (tests/packaging/check_man_pages.sh reads the man page itself.)
execute_process(COMMAND ${PREFIX}/bin/tocdlab --version OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^tocdlab ${VERSION}")
  message(FATAL_ERROR "installed tocdlab --version: '${out}' (exit ${rc})")
endif()

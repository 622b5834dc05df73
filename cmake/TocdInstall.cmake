# Install rules and the Debian package (docs/packaging.md):
#   cmake --install build/dev --prefix /usr/local
#   (cd build/dev && cpack -G DEB)     # tocdlab_<version>_<arch>.deb
include(GNUInstallDirs)

install(TARGETS tocdlab RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET tocdlab-gui)
  install(TARGETS tocdlab-gui RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

# The README and the docs keep the source tree's layout under the doc directory (README.md,
# docs/, examples/, protocols/), so every relative link in them resolves where they are
# installed (packaging.installed_links). The examples and protocols are also installed as data
# beside the programs, without the examples' README (its links point into the docs).
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs ${PROJECT_SOURCE_DIR}/examples ${PROJECT_SOURCE_DIR}/protocols
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tocdlab/examples
        PATTERN README.md EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/protocols/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tocdlab/protocols)
install(FILES ${PROJECT_SOURCE_DIR}/scripts/completion/tocdlab.bash
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME tocdlab)

# Man pages from the programs' own --help and --version, so they never drift from the code.
# tocdlab.1 holds every subcommand's options too: help2man reads scripts/man/tocdlab-help-all,
# which prints `tocdlab --help` and then each `tocdlab <command> --help`, nested ones included.
# help2man runs in a UTF-8 locale (--locale), else it writes the em dash of the help as "???".
# The pages are installed gzip -9n (compressed, no name or time stamp: reproducible), as
# Debian policy wants them.
find_program(TOCD_HELP2MAN help2man)
if(NOT TOCD_HELP2MAN)
  message(FATAL_ERROR "tocdlab needs help2man to write its man pages. Install it with:\n"
                      "  apt-get install help2man\n"
                      "(or run scripts/bootstrap, which installs every package tocdlab needs)")
endif()
find_program(TOCD_GZIP gzip REQUIRED)
set(man_dir ${CMAKE_BINARY_DIR}/man)
# help2man names the page after the program it runs: a `tocdlab` that prints the whole help.
file(GENERATE OUTPUT ${man_dir}/help-all/tocdlab
     CONTENT "#!/bin/sh\nexec '${PROJECT_SOURCE_DIR}/scripts/man/tocdlab-help-all' '$<TARGET_FILE:tocdlab>' \"$@\"\n"
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
# tocd_man_page(<target> <program> <one-line description>)
function(tocd_man_page target program description)
  set(page ${man_dir}/${target}.1)
  add_custom_command(
    OUTPUT ${page}.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
    # The window's --help parses before any window opens; offscreen needs no display.
    COMMAND ${CMAKE_COMMAND} -E env QT_QPA_PLATFORM=offscreen ${TOCD_HELP2MAN} --locale=C.UTF-8 --no-info
            --no-discard-stderr --name=${description} --version-string=${PROJECT_VERSION} --output=${page} ${program}
    COMMAND ${TOCD_GZIP} -9n -f ${page}
    DEPENDS ${target} ${PROJECT_SOURCE_DIR}/scripts/man/tocdlab-help-all
    COMMENT "Man page ${target}.1.gz from ${target} --help"
    VERBATIM)
  add_custom_target(${target}_man ALL DEPENDS ${page}.gz)
  install(FILES ${page}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endfunction()
tocd_man_page(tocdlab ${man_dir}/help-all/tocdlab "tissue optical clearing lab workbench (command line)")
if(TARGET tocdlab-gui)
  tocd_man_page(tocdlab-gui $<TARGET_FILE:tocdlab-gui> "tissue optical clearing lab workbench (window)")
endif()

include(TocdDebianPackage)

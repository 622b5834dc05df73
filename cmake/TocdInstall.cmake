# Install rules and the Debian package (docs/packaging.md):
#   cmake --install build/dev --prefix /usr/local
#   (cd build/dev && cpack -G DEB)     # tocdlab_<version>_<arch>.deb
include(GNUInstallDirs)

install(TARGETS tocdlab RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET tocdlab-gui)
  install(TARGETS tocdlab-gui RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tocdlab/examples)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/protocols/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tocdlab/protocols)
install(FILES ${PROJECT_SOURCE_DIR}/scripts/completion/tocdlab.bash
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME tocdlab)

# Man pages from the programs' own --help and --version, so they never drift from the code.
find_program(TOCD_HELP2MAN help2man)
if(NOT TOCD_HELP2MAN)
  message(FATAL_ERROR "tocdlab needs help2man to write its man pages. Install it with:\n"
                      "  apt-get install help2man\n"
                      "(or run scripts/bootstrap, which installs every package tocdlab needs)")
endif()
set(man_dir ${CMAKE_BINARY_DIR}/man)
# tocd_man_page(<target> <one-line description>)
function(tocd_man_page target description)
  set(page ${man_dir}/${target}.1)
  add_custom_command(
    OUTPUT ${page}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
    # The window's --help parses before any window opens; offscreen needs no display.
    COMMAND ${CMAKE_COMMAND} -E env QT_QPA_PLATFORM=offscreen ${TOCD_HELP2MAN} --no-info --no-discard-stderr
            --name=${description} --version-string=${PROJECT_VERSION} --output=${page} $<TARGET_FILE:${target}>
    DEPENDS ${target}
    COMMENT "Man page ${target}.1 from ${target} --help"
    VERBATIM)
  add_custom_target(${target}_man ALL DEPENDS ${page})
  install(FILES ${page} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endfunction()
tocd_man_page(tocdlab "tissue optical clearing lab workbench (command line)")
if(TARGET tocdlab-gui)
  tocd_man_page(tocdlab-gui "tissue optical clearing lab workbench (window)")
endif()

# The .deb. Library dependencies come from dpkg-shlibdeps over the installed binaries; the
# font is for the text of `tocdlab plot` figures (Qt finds no font on a bare system).
set(CPACK_PACKAGE_NAME tocdlab)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_DESCRIPTION
    "Drives the instruments of a pin-compression rig (Modbus, USBTMC, SCPI), records every reading in a \
SQLite database and predicts each step's light transmission with finite elements and photon Monte \
Carlo; command line tocdlab and Qt window tocdlab-gui.")
set(CPACK_PACKAGE_CONTACT "tocdlab maintainers <tocdlab@localhost>")
set(CPACK_PACKAGE_INSTALL_DIRECTORY tocdlab)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "fonts-dejavu-core")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "bash-completion, openmpi-bin")
include(CPack)

# The .deb (docs/packaging.md): `cd build/release && cpack -G DEB`. Everything Debian policy
# and lintian --pedantic ask of a binary package that CPack does not write itself: the
# machine-readable copyright file, the changelog, a real maintainer, description lines of at
# most 80 columns, and recommends that match the build.
set(TOCD_PACKAGE_MAINTAINER "tocdlab maintainers <maintainers@tocdlab.org>"
    CACHE STRING "Maintainer field of the .deb: Name <address>")

set(deb_dir ${CMAKE_BINARY_DIR}/deb)
# /usr/share/doc/tocdlab/copyright (DEP-5) with the licence text of LICENSE: each line
# indented by one space, blank lines as " .", as the format wants it.
file(STRINGS ${PROJECT_SOURCE_DIR}/LICENSE license_lines)
set(TOCD_LICENSE_PARAGRAPH "")
foreach(line IN LISTS license_lines)
  string(REGEX REPLACE "[ \t]+$" "" line "${line}")
  if(line STREQUAL "")
    string(APPEND TOCD_LICENSE_PARAGRAPH " .\n")
  else()
    string(APPEND TOCD_LICENSE_PARAGRAPH " ${line}\n")
  endif()
endforeach()
string(REGEX REPLACE "\n$" "" TOCD_LICENSE_PARAGRAPH "${TOCD_LICENSE_PARAGRAPH}")
configure_file(${PROJECT_SOURCE_DIR}/packaging/deb/copyright.in ${deb_dir}/copyright @ONLY)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/LICENSE)
install(FILES ${deb_dir}/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The changelog of a native package (its version has no Debian revision) is changelog.gz. Its
# newest entry must be this version: a release adds an entry to packaging/deb/changelog.
set(changelog ${PROJECT_SOURCE_DIR}/packaging/deb/changelog)
file(STRINGS ${changelog} changelog_head LIMIT_COUNT 1)
if(NOT changelog_head MATCHES "^tocdlab \\(${PROJECT_VERSION}\\) ")
  message(FATAL_ERROR "packaging/deb/changelog starts with '${changelog_head}', not an entry for "
                      "tocdlab ${PROJECT_VERSION}: add one (dch -v ${PROJECT_VERSION} --changelog ${changelog})")
endif()
add_custom_command(
  OUTPUT ${deb_dir}/changelog.gz
  COMMAND ${TOCD_GZIP} -9n -c ${changelog} > ${deb_dir}/changelog.gz
  DEPENDS ${changelog}
  COMMENT "changelog.gz of the package")
add_custom_target(tocdlab_changelog ALL DEPENDS ${deb_dir}/changelog.gz)
install(FILES ${deb_dir}/changelog.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})

# Library dependencies come from dpkg-shlibdeps over the installed binaries; the font is for
# the text of `tocdlab plot` figures (Qt finds no font on a bare system).
set(CPACK_PACKAGE_NAME tocdlab)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
# Lines of at most 80 columns: CPack copies each line as it is.
set(CPACK_PACKAGE_DESCRIPTION
    "Drives the instruments of a pin-compression rig (Modbus, USBTMC, SCPI),
records every reading in a SQLite database and predicts each step's light
transmission with finite elements and photon Monte Carlo. Command line
tocdlab and Qt window tocdlab-gui.")
set(CPACK_PACKAGE_CONTACT "${TOCD_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${TOCD_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_INSTALL_DIRECTORY tocdlab)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "fonts-dejavu-core")
# mpirun only serves a build that can share runs across ranks.
if(TOCD_WITH_MPI)
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "bash-completion, openmpi-bin")
else()
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "bash-completion")
endif()
include(CPack)

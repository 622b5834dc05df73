# Every third-party dependency comes from a Debian 12 package. A missing one stops the
# configure step with the name of the package that provides it.
find_package(PkgConfig REQUIRED)

# tocd_require_package(<find_package name> <debian package> [find_package args...])
macro(tocd_require_package name debian_package)
  find_package(${name} ${ARGN} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR
      "tocdlab needs ${name}, which was not found. Install it with:\n"
      "  apt-get install ${debian_package}\n"
      "(or run scripts/bootstrap, which installs every package tocdlab needs)")
  endif()
endmacro()

# tocd_require_pkgconfig(<imported target> <pkg-config module> <debian package>)
function(tocd_require_pkgconfig target module debian_package)
  pkg_check_modules(${target} QUIET IMPORTED_TARGET GLOBAL ${module})
  if(NOT ${target}_FOUND)
    message(FATAL_ERROR
      "tocdlab needs ${module} (pkg-config), which was not found. Install it with:\n"
      "  apt-get install ${debian_package}\n"
      "(or run scripts/bootstrap, which installs every package tocdlab needs)")
  endif()
endfunction()

# tocd_require_header_library(<imported target> <header> <library> <debian package>)
function(tocd_require_header_library target header library debian_package)
  find_path(${target}_INCLUDE_DIR ${header})
  find_library(${target}_LIBRARY ${library})
  if(NOT ${target}_INCLUDE_DIR OR NOT ${target}_LIBRARY)
    message(FATAL_ERROR
      "tocdlab needs ${header} and lib${library}, which were not found. Install them with:\n"
      "  apt-get install ${debian_package}\n"
      "(or run scripts/bootstrap, which installs every package tocdlab needs)")
  endif()
  add_library(${target} UNKNOWN IMPORTED GLOBAL)
  set_target_properties(${target} PROPERTIES IMPORTED_LOCATION "${${target}_LIBRARY}"
                                             INTERFACE_INCLUDE_DIRECTORIES "${${target}_INCLUDE_DIR}")
endfunction()

tocd_require_package(Threads libc6-dev)
tocd_require_package(OpenMP libgomp1)
tocd_require_package(Eigen3 libeigen3-dev 3.4 NO_MODULE)
tocd_require_package(SQLite3 libsqlite3-dev)
tocd_require_package(ZLIB zlib1g-dev)
tocd_require_package(fmt libfmt-dev)
tocd_require_package(spdlog libspdlog-dev)
tocd_require_package(CLI11 libcli11-dev)
tocd_require_package(tomlplusplus libtomlplusplus-dev)
tocd_require_package(nlohmann_json nlohmann-json3-dev)
tocd_require_pkgconfig(tocd_libmodbus libmodbus libmodbus-dev)
tocd_require_pkgconfig(tocd_libusb libusb-1.0 libusb-1.0-0-dev)
# The PostgreSQL backend of db/ (a lab's shared server): the client library only.
tocd_require_pkgconfig(tocd_libpq libpq libpq-dev)
tocd_require_header_library(tocd_tetgen tetgen.h tet libtet1.5-dev)
# Debian's libtet is built as a library: tetgen.h must see TETLIBRARY.
set_target_properties(tocd_tetgen PROPERTIES INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)

find_path(TOCD_RANDOM123_INCLUDE_DIR Random123/philox.h)
if(NOT TOCD_RANDOM123_INCLUDE_DIR)
  message(FATAL_ERROR "tocdlab needs Random123, which was not found. Install it with:\n"
                      "  apt-get install librandom123-dev")
endif()
add_library(tocd_random123 INTERFACE IMPORTED GLOBAL)
set_target_properties(tocd_random123 PROPERTIES INTERFACE_INCLUDE_DIRECTORIES
                                                "${TOCD_RANDOM123_INCLUDE_DIR}")

if(TOCD_WITH_GUI)
  tocd_require_package(Qt6 "qt6-base-dev qt6-charts-dev libqt6opengl6-dev" COMPONENTS Widgets Charts Test)
endif()
if(TOCD_WITH_PLOT)
  tocd_require_package(Qt6 "qt6-base-dev qt6-svg-dev" COMPONENTS Gui Svg)
endif()
if(TOCD_BUILD_TESTS)
  tocd_require_package(GTest "libgtest-dev libgmock-dev")
endif()
if(TOCD_WITH_MPI)
  tocd_require_package(MPI "libopenmpi-dev")
endif()

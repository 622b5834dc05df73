# Hardening of every build, as Debian builds its packages (dpkg-buildflags, hardening=+all):
# - Release: glibc's checked variants of memcpy, sprintf, read, ... where the buffer size is
#   known at compile time (_FORTIFY_SOURCE=2 needs optimisation, hence Release only);
# - stack canaries in functions with arrays or address-taken locals;
# - stack clash protection: large frames are probed page by page, so no allocation can jump
#   over the guard page into another mapping;
# - control-flow protection (CET: endbr64 landing pads, shadow-stack ready);
# - position-independent executables (ASLR), and relocations read-only after start-up with
#   every symbol bound then (RELRO + BIND_NOW), so the GOT cannot be overwritten.
# The sanitizer presets (clang) take the same flags; only FORTIFY stays out of them.
include(CheckPIESupported)
check_pie_supported(LANGUAGES C CXX)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  add_compile_options("$<$<CONFIG:Release>:-U_FORTIFY_SOURCE>" "$<$<CONFIG:Release>:-D_FORTIFY_SOURCE=2>"
                      -fstack-protector-strong -fstack-clash-protection)
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64|i.86)$")
    add_compile_options(-fcf-protection)
  endif()
  add_link_options(LINKER:-z,relro LINKER:-z,now)
endif()

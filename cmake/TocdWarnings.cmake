# Warning flags shared by every tocdlab target (interface target, linked PRIVATE).
add_library(tocd_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(tocd_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow=local
                                                 -Wnon-virtual-dtor)
elseif(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  # clang's name for GCC's -Wshadow=local
  target_compile_options(tocd_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow-uncaptured-local
                                                 -Wnon-virtual-dtor)
endif()

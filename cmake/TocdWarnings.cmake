# Warning flags shared by every tocdlab target (interface target, linked PRIVATE).
add_library(tocd_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(tocd_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow=local
                                                 -Wnon-virtual-dtor)
endif()

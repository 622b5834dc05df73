# Release builds: glibc's checked variants of memcpy, sprintf, read, ... where the buffer size is
# known at compile time (_FORTIFY_SOURCE=2 needs optimisation, hence Release only) and stack
# canaries in functions with arrays or address-taken locals.
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  add_compile_options("$<$<CONFIG:Release>:-U_FORTIFY_SOURCE>" "$<$<CONFIG:Release>:-D_FORTIFY_SOURCE=2>"
                      "$<$<CONFIG:Release>:-fstack-protector-strong>")
endif()

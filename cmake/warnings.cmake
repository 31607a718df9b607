# Warnings for our own targets only (not for third-party headers); -Werror with DYNPM_WERROR (CI).
add_library(dynpm_warnings INTERFACE)
target_compile_options(dynpm_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                       -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
                       $<$<BOOL:${DYNPM_WERROR}>:-Werror>)
# GCC 12 at -O3 (Release) warns -Wrestrict on ordinary std::string appends it has inlined
# (GCC bug 105329, fixed in 13): false positives in several files, so it is off for GCC 12.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(dynpm_warnings INTERFACE -Wno-restrict)
endif()

# Warnings for our own targets only (not for third-party headers); -Werror with DYNPM_WERROR (CI).
add_library(dynpm_warnings INTERFACE)
target_compile_options(dynpm_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                       -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
                       $<$<BOOL:${DYNPM_WERROR}>:-Werror>)

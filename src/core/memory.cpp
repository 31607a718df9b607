#include "dynpm/core.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dynpm {

void return_freed_arrays_to_the_system() {
#if defined(__GLIBC__)
  // Setting the threshold also turns off glibc's moving of it (mallopt(3)).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
}

}  // namespace dynpm

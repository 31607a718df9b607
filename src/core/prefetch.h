// Asking for memory ahead of use, in a form the optimizer keeps.
// Internal: modules include it as "core/prefetch.h".
#pragma once

namespace dynpm {

// GCC 12 at -O2 deletes a loop whose only effect is __builtin_prefetch (under -ffinite-loops it
// counts as no effect), so loops of bare prefetches were never made. The empty asm that takes the
// address is an effect the loop must keep, and costs no instruction.
template <bool kForWrite = false>
inline void prefetch(const void* address) {
#if defined(__GNUC__)
  __builtin_prefetch(address, kForWrite ? 1 : 0);
  asm volatile("" : : "r"(address));
#else
  (void)address;
#endif
}

}  // namespace dynpm

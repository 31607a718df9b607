// Memory a shrinking array no longer uses, handed back to the system while the array keeps it.
// Internal: modules include it as "core/pages.h".
#pragma once

#include <type_traits>
#include <vector>

namespace dynpm {

// The whole pages inside [begin, end) go back to the system (Linux: madvise MADV_DONTNEED;
// elsewhere nothing happens). The range stays the caller's: touched again it reads as zeros.
void release_pages(const void* begin, const void* end);

// The free memory the C library keeps in its heaps (arrays under 1 MB freed below arrays still
// in use, and worker threads' heaps) back to the system: glibc malloc_trim(); elsewhere nothing.
void release_free_heap();

// A vector's capacity past its size, without the copy of shrink_to_fit(): a vector writes its
// elements before it reads them, so the released pages are never read as they were.
template <class T>
void release_unused_capacity(const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  release_pages(v.data() + v.size(), v.data() + v.capacity());
}

}  // namespace dynpm

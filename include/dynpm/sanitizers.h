// dynpm/sanitizers.h — whether this build runs under AddressSanitizer. ASan reserves terabytes
// of address space, so an address-space limit (RLIMIT_AS, `ulimit -v`) cannot be set under it.
#pragma once

namespace dynpm {

#if defined(__SANITIZE_ADDRESS__)  // gcc
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace dynpm

// libFuzzer entry point: the frd reader on arbitrary bytes (fuzz/targets.h: run_frd).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynpm::fuzz::run_frd(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

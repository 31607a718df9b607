// libFuzzer entry point: the obj reader on arbitrary bytes (fuzz/targets.h: run_obj).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynpm::fuzz::run_obj(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

// libFuzzer entry point: the vtk reader on arbitrary bytes (fuzz/targets.h: run_vtk).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynpm::fuzz::run_vtk(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

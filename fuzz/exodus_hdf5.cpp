// libFuzzer entry point: the exodus reader on arbitrary bytes made to start as an HDF5 file
// (fuzz/targets.h: run_exodus_hdf5), so that every input is read in the forked child and the
// finding looked for is dynpm itself crashing, failing a check or hanging. As in fuzz_exodus,
// the child forgets libFuzzer's death callback: libhdf5 tripping a sanitizer there is contained.
#include <pthread.h>
#include <sanitizer/common_interface_defs.h>

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "targets.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pthread_atfork(nullptr, nullptr, [] { __sanitizer_set_death_callback(nullptr); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynpm::fuzz::run_exodus_hdf5(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

// libFuzzer entry point: the exodus reader on arbitrary bytes (fuzz/targets.h: run_exodus).
//
// HDF5 (netCDF-4) inputs are read in a forked child (src/io/contained_read.h), a copy of this
// process with libFuzzer's death callback in it: when libhdf5 trips a sanitizer there, libFuzzer
// would write the input as a "crash" of this harness although dynpm survived. The child forgets
// the callback: a finding is dynpm (this process) crashing, failing a check or hanging. The
// child's sanitizer reports still go to the log, where reports with dynpm frames are looked for.
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
  dynpm::fuzz::run_exodus(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

// for_each_step(): the one pass over an animation's steps that the simplifier and the build
// share, decoding several steps at once on sources that allow it.
#include <algorithm>

#include "dynpm/core.h"
#include "parallel.h"

namespace dynpm {

Status for_each_step(const FrameSource& frames, std::span<const size_t> steps, unsigned threads,
                     const std::function<Status(size_t, std::span<const float>)>& use) {
  const size_t floats = size_t{frames.vertex_count()} * 3;
  const size_t batch =
      frames.parallel_reads() ? std::min<size_t>(thread_count(threads), steps.size()) : 1;
  std::vector<std::vector<float>> buffers(std::max<size_t>(batch, 1), std::vector<float>(floats));
  std::vector<Status> read(buffers.size());
  for (size_t first = 0; first < steps.size(); first += buffers.size()) {
    const size_t count = std::min(buffers.size(), steps.size() - first);
    // Each read writes only its own buffer and status: the batch is the same on any thread count.
    parallel_for(count, count, static_cast<unsigned>(count), [&](size_t begin, size_t end, size_t) {
      for (size_t j = begin; j < end; ++j) read[j] = frames.read_step(steps[first + j], buffers[j]);
    });
    for (size_t j = 0; j < count; ++j) {
      if (!read[j].ok()) return read[j];
      DYNPM_RETURN_IF_ERROR(use(first + j, buffers[j]));
    }
  }
  return {};
}

}  // namespace dynpm

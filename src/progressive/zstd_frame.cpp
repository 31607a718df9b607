// One zstd frame of a .dpm chunk (zstd_frame.h).
#include "zstd_frame.h"

#include <zstd.h>

#include <algorithm>
#include <memory>

namespace dynpm::progressive {
namespace {

struct DStreamFree {
  void operator()(ZSTD_DStream* d) const { ZSTD_freeDStream(d); }
};

}  // namespace

std::string inflate(std::string_view frame, uint64_t raw, std::string& out) {
  std::unique_ptr<ZSTD_DStream, DStreamFree> stream(ZSTD_createDStream());
  if (!stream || ZSTD_isError(ZSTD_initDStream(stream.get()))) return "no memory for zstd";
  ZSTD_inBuffer in{frame.data(), frame.size(), 0};
  out.clear();
  size_t produced = 0;
  char spill;  // where output beyond `raw` would go: any is an error
  for (;;) {
    if (produced == out.size() && out.size() < raw)
      out.resize(std::min<uint64_t>(raw, std::max<uint64_t>(2 * out.size(), 1 << 20)));
    const bool full = produced == out.size();
    ZSTD_outBuffer o{full ? &spill : out.data() + produced, full ? 1 : out.size() - produced, 0};
    const size_t consumed = in.pos;
    const size_t left = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(left)) return ZSTD_getErrorName(left);
    if (full && o.pos > 0) return "it holds more bytes than its header says";
    produced += o.pos;
    if (left == 0) break;  // the frame is complete
    if (o.pos == 0 && in.pos == consumed) return "the frame is cut short";
  }
  if (produced != raw) return "it holds fewer bytes than its header says";
  if (in.pos != in.size) return "bytes after its zstd frame";
  return {};
}

}  // namespace dynpm::progressive

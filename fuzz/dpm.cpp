// libFuzzer entry point: the dpm reader on arbitrary bytes (fuzz/targets.h: run_dpm), with a
// mutator that reaches the payloads behind the checksums.
#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <string_view>

#include "progressive/dpm_format.h"
#include "targets.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {

uint32_t u32_at(const std::string& bytes, size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

// A random change to a .dpm nearly always breaks a chunk's CRC-32, and the reader stops at the
// check. So three mutants in four are made inside one chunk's payload (inflated first when it
// is a zstd frame, then stored plain) and the chunk's sizes and checksum are made right again;
// the fourth is libFuzzer's own anywhere in the file, so the checks themselves stay fuzzed.
size_t mutate_inside_a_chunk(uint8_t* data, size_t size, size_t max_size, unsigned seed) {
  using dynpm::progressive::kChunkHeaderSize;
  std::minstd_rand random(seed);
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::vector<size_t> chunks;  // offsets of the whole chunks after signature and version
  for (size_t at = 12; at + kChunkHeaderSize <= size;) {
    const size_t end = at + kChunkHeaderSize + u32_at(bytes, at + 8);
    if (end > size) break;
    chunks.push_back(at);
    at = end;
  }
  if (random() % 4 == 0 || chunks.empty()) return LLVMFuzzerMutate(data, size, max_size);
  const size_t at = chunks[random() % chunks.size()];
  const uint32_t flags = u32_at(bytes, at + 4), stored = u32_at(bytes, at + 8);
  const uint32_t raw = u32_at(bytes, at + 12);
  std::string payload = bytes.substr(at + kChunkHeaderSize, stored);
  bool plain = (flags & 1) == 0;
  if (!plain && raw <= (uint32_t{1} << 24)) {
    std::string inflated(raw, '\0');
    const size_t got = ZSTD_decompress(inflated.data(), raw, payload.data(), payload.size());
    if (!ZSTD_isError(got) && got == raw) payload = std::move(inflated), plain = true;
  }
  const size_t rest = size - stored - kChunkHeaderSize;
  if (rest + kChunkHeaderSize >= max_size) return LLVMFuzzerMutate(data, size, max_size);
  const size_t room = max_size - rest - kChunkHeaderSize;
  if (payload.size() > room) return LLVMFuzzerMutate(data, size, max_size);
  const size_t length = payload.size();
  payload.resize(room);
  payload.resize(LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(payload.data()), length, room));
  std::string out = bytes.substr(0, at);
  out.append(kChunkHeaderSize, '\0');
  // A frame that did not inflate keeps its flag: the mutant then tests the zstd path.
  dynpm::progressive::write_chunk_header(out.data() + at, bytes.substr(at, 4), !plain,
                                         payload.size(), plain ? payload.size() : raw,
                                         dynpm::progressive::crc32(payload));
  out += payload;
  out += bytes.substr(at + kChunkHeaderSize + stored);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size,
                                          unsigned int seed) {
  return mutate_inside_a_chunk(data, size, max_size, seed);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dynpm::fuzz::run_dpm(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

// The THMB chunk (docs/FORMAT.md "Thumbnail: THMB"): a PNG picture of the model that a catalogue
// shows. Written just before END, where a file's other chunks are all in place, so adding one to
// an existing file moves nothing else; found by walking the chunk headers, without reading the
// payloads between them.
#include <cstring>
#include <fstream>

#include "dpm_format.h"
#include "dynpm/progressive.h"

namespace dynpm {
namespace {

using namespace progressive;

// A thumbnail is a few tens of KiB; a larger payload is not read into memory.
constexpr uint32_t kMaxThumbnail = 4u << 20;

struct ChunkHeader {
  std::string tag;
  uint32_t flags = 0, stored = 0, raw = 0, crc = 0;
};

ChunkHeader parse_header(const char* bytes) {
  ChunkHeader h;
  h.tag.assign(bytes, 4);
  std::memcpy(&h.flags, bytes + 4, 4);
  std::memcpy(&h.stored, bytes + 8, 4);
  std::memcpy(&h.raw, bytes + 12, 4);
  std::memcpy(&h.crc, bytes + 16, 4);
  return h;
}

}  // namespace

Result<std::string> with_thumbnail(std::string_view dpm, std::string_view png,
                                   const std::string& name) {
  const size_t first = kMagic.size() + 4;
  if (dpm.size() < first || dpm.substr(0, kMagic.size()) != kMagic)
    return Status::error(name + ": not a .dpm file");
  std::string out(dpm.substr(0, first));
  for (size_t at = first;;) {
    if (dpm.size() - at < kChunkHeaderSize)
      return Status::error(name + ": byte " + std::to_string(at) +
                           ": the file ends before END (a partial file gets no thumbnail)");
    const ChunkHeader h = parse_header(dpm.data() + at);
    const size_t next = at + kChunkHeaderSize + h.stored;
    if (next > dpm.size())
      return Status::error(name + ": byte " + std::to_string(at) + ": " + h.tag +
                           " chunk runs past the end of the file");
    if (h.tag == "END ") {
      if (next != dpm.size())
        return Status::error(name + ": byte " + std::to_string(next) + ": bytes after END");
      put_chunk(out, kThumbnailTag, png, false);  // PNG data is compressed already
      out.append(dpm.substr(at));
      return out;
    }
    if (h.tag != kThumbnailTag) out.append(dpm.substr(at, next - at));  // an old one is replaced
    at = next;
  }
}

Result<std::optional<std::string>> read_dpm_thumbnail(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return Status::error(path + ": cannot open");
  const uint64_t size = static_cast<uint64_t>(in.tellg());
  char start[12];
  if (!in.seekg(0) || !in.read(start, sizeof start) ||
      std::string_view(start, kMagic.size()) != kMagic)
    return Status::error(path + ": not a .dpm file");
  std::optional<std::string> thumbnail;
  char header[kChunkHeaderSize];
  for (uint64_t at = sizeof start;;
       at += kChunkHeaderSize + uint64_t{parse_header(header).stored}) {
    if (size - at < kChunkHeaderSize || !in.seekg(static_cast<std::streamoff>(at)) ||
        !in.read(header, sizeof header))
      return Status::error(path + ": byte " + std::to_string(at) +
                           ": the file ends before END (still being written?)");
    const ChunkHeader h = parse_header(header);
    if (h.tag == "END ") {
      if (at + kChunkHeaderSize != size)
        return Status::error(path + ": byte " + std::to_string(at + kChunkHeaderSize) +
                             ": bytes after END");
      return thumbnail;
    }
    if (h.tag != kThumbnailTag) continue;
    auto bad = [&](const std::string& why) {
      return Status::error(path + ": byte " + std::to_string(at) + ": THMB chunk: " + why);
    };
    if (h.flags != 0 || h.stored != h.raw) return bad("compressed or with unequal sizes");
    if (h.stored > kMaxThumbnail) return bad("larger than 4 MiB");
    std::string png(h.stored, '\0');
    if (!in.read(png.data(), h.stored)) return bad("the file ends inside it");
    if (crc32(png) != h.crc) return bad("wrong checksum");
    thumbnail = std::move(png);
  }
}

}  // namespace dynpm

// PNG (ISO/IEC 15948) and the zlib/deflate stream it holds (RFC 1950, RFC 1951): png.h.
#include "png.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <optional>
#include <queue>
#include <utility>
#include <vector>

#include "progressive/dpm_format.h"  // crc32, the one of the .dpm chunks: PNG's is the same

namespace dynpm::pipeline {
namespace {

constexpr std::array<uint16_t, 29> kLengthBase = {3,  4,  5,  6,   7,   8,   9,   10,  11, 13,
                                                  15, 17, 19, 23,  27,  31,  35,  43,  51, 59,
                                                  67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::array<uint8_t, 29> kLengthExtra = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                                  2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::array<uint16_t, 30> kDistanceBase = {
    1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
    193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::array<uint8_t, 30> kDistanceExtra = {0, 0, 0,  0,  1,  1,  2,  2,  3,  3,
                                                    4, 4, 5,  5,  6,  6,  7,  7,  8,  8,
                                                    9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
constexpr size_t kWindow = 32768;
constexpr size_t kMinMatch = 3, kMaxMatch = 258;
constexpr int kChainSteps = 256;  // candidates tried per position (32: +7–10 % on the boxes)
constexpr int kHashBits = 15;
constexpr int kLongestCode = 15, kLongestLengthCode = 7;  // RFC 1951's limits
constexpr uint32_t kEndOfBlock = 256;
// A palette image maps a colour outside its 256 to the nearest of them (RGB distance) if that
// differs by at most this on every channel: on a thumbnail such colours are a few blended edge
// pixels (measured on the crash boxes: 12–22 at most).
constexpr int kPaletteTolerance = 24;
// The code lengths' own code: its symbols in the order their lengths are sent.
constexpr std::array<uint8_t, 19> kLengthCodeOrder = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                                      11, 4,  12, 3, 13, 2, 14, 1, 15};

// Deflate's bit order: values least significant bit first, Huffman codes most significant first.
class BitWriter {
 public:
  std::string bytes;
  void bits(uint32_t value, int count) {
    for (int i = 0; i < count; ++i) bit((value >> i) & 1);
  }
  void code(uint32_t code, int length) {
    for (int i = length - 1; i >= 0; --i) bit((code >> i) & 1);
  }
  void flush() {
    if (used_) bytes.push_back(static_cast<char>(acc_)), acc_ = 0, used_ = 0;
  }

 private:
  void bit(uint32_t b) {
    acc_ |= b << used_;
    if (++used_ == 8) flush();
  }
  uint32_t acc_ = 0;
  int used_ = 0;
};

// What LZ77 found: a literal byte (distance 0) or a match.
struct Token {
  uint16_t length_or_byte;
  uint16_t distance;
};

// Length and distance symbols (RFC 1951, 3.2.5), with their extra bits' value.
struct Symbol {
  uint32_t code, extra;
  uint8_t extra_bits;
};
Symbol length_symbol(size_t length) {
  size_t l = kLengthBase.size() - 1;
  while (kLengthBase[l] > length) --l;
  return {static_cast<uint32_t>(257 + l), static_cast<uint32_t>(length - kLengthBase[l]),
          kLengthExtra[l]};
}
Symbol distance_symbol(size_t distance) {
  size_t d = kDistanceBase.size() - 1;
  while (kDistanceBase[d] > distance) --d;
  return {static_cast<uint32_t>(d), static_cast<uint32_t>(distance - kDistanceBase[d]),
          kDistanceExtra[d]};
}

// Greedy LZ77 with one step of lazy evaluation (a literal first when the next position matches
// longer), over hash chains of 3-byte prefixes.
std::vector<Token> lz77(std::span<const uint8_t> in) {
  std::vector<int64_t> head(size_t{1} << kHashBits, -1), previous(in.size(), -1);
  auto hash = [&](size_t i) {
    return ((uint32_t{in[i]} << 10) ^ (uint32_t{in[i + 1]} << 5) ^ in[i + 2]) &
           ((1u << kHashBits) - 1);
  };
  auto insert = [&](size_t i) {
    if (i + kMinMatch > in.size()) return;
    const uint32_t h = hash(i);
    previous[i] = head[h];
    head[h] = static_cast<int64_t>(i);
  };
  auto longest = [&](size_t i) {
    std::pair<size_t, size_t> best{0, 0};  // length, distance
    if (i + kMinMatch > in.size()) return best;
    int64_t candidate = head[hash(i)];
    const size_t limit = std::min(kMaxMatch, in.size() - i);
    for (int step = 0;
         step < kChainSteps && candidate >= 0 && i - static_cast<size_t>(candidate) <= kWindow;
         ++step, candidate = previous[static_cast<size_t>(candidate)]) {
      const size_t c = static_cast<size_t>(candidate);
      size_t n = 0;
      while (n < limit && in[c + n] == in[i + n]) ++n;
      if (n > best.first) best = {n, i - c};
      if (n == limit) break;
    }
    return best;
  };
  std::vector<Token> tokens;
  for (size_t i = 0; i < in.size();) {
    const auto [length, distance] = longest(i);
    insert(i);
    if (length >= kMinMatch && length < kMaxMatch && longest(i + 1).first > length) {
      tokens.push_back({in[i], 0});  // the longer match at i + 1 is taken next
      ++i;
    } else if (length >= kMinMatch) {
      tokens.push_back({static_cast<uint16_t>(length), static_cast<uint16_t>(distance)});
      for (size_t k = 1; k < length; ++k) insert(i + k);
      i += length;
    } else {
      tokens.push_back({in[i], 0});
      ++i;
    }
  }
  return tokens;
}

// Huffman code lengths for `counts`, none longer than `limit` (an unused symbol gets 0). Two
// symbols at least are given a code (symbols 0 and 1 if need be): a code of one symbol is
// incomplete, which inflate refuses for the code lengths' own code. Over the limit, the counts
// are halved (kept ≥ 1) and the code made again: rare on a thumbnail's few hundred symbols.
std::vector<uint8_t> code_lengths(std::vector<uint32_t> counts, int limit) {
  const uint32_t n = static_cast<uint32_t>(counts.size());
  for (uint32_t s = 0; s < 2 && std::count(counts.begin(), counts.end(), 0u) + 2 > n; ++s)
    counts[s] = std::max(counts[s], 1u);
  for (;;) {
    using Node = std::pair<uint64_t, uint32_t>;  // weight, node (leaves first, then merges)
    std::priority_queue<Node, std::vector<Node>, std::greater<>> heap;
    for (uint32_t s = 0; s < n; ++s)
      if (counts[s] > 0) heap.push({counts[s], s});
    std::vector<uint32_t> parent(2 * size_t{n}, 0);
    uint32_t next = n;
    while (heap.size() > 1) {
      const Node a = heap.top();
      heap.pop();
      const Node b = heap.top();
      heap.pop();
      parent[a.second] = parent[b.second] = next;
      heap.push({a.first + b.first, next++});
    }
    std::vector<uint8_t> lengths(n, 0);
    // A parent is made after its children: depths from the root down by falling node number.
    std::vector<uint16_t> depth(next, 0);
    int deepest = 0;
    for (uint32_t k = next - 1; k-- > 0;) {
      if (k < n && counts[k] == 0) continue;
      depth[k] = static_cast<uint16_t>(depth[parent[k]] + 1);
      if (k < n) lengths[k] = static_cast<uint8_t>(std::min<int>(depth[k], 255));
      deepest = std::max<int>(deepest, depth[k]);
    }
    if (deepest <= limit) return lengths;
    for (uint32_t& c : counts)
      if (c > 0) c = (c + 1) / 2;
  }
}

// Canonical codes for lengths (RFC 1951, 3.2.2).
std::vector<uint32_t> canonical_codes(const std::vector<uint8_t>& lengths) {
  std::array<uint32_t, kLongestCode + 2> count{}, next{};
  for (uint8_t l : lengths)
    if (l > 0) ++count[l];
  for (int bits = 1; bits <= kLongestCode + 1; ++bits)
    next[bits] = (next[bits - 1] + count[bits - 1]) << 1;
  std::vector<uint32_t> codes(lengths.size(), 0);
  for (size_t s = 0; s < lengths.size(); ++s)
    if (lengths[s] > 0) codes[s] = next[lengths[s]]++;
  return codes;
}

// The code lengths as sent: runs of zeros as 17 (3–10) and 18 (11–138), repeats of the length
// before as 16 (3–6); each item a symbol and its extra bits' value.
std::vector<std::pair<uint8_t, uint8_t>> run_length(const std::vector<uint8_t>& lengths) {
  std::vector<std::pair<uint8_t, uint8_t>> items;
  for (size_t i = 0; i < lengths.size();) {
    size_t run = 1;
    while (i + run < lengths.size() && lengths[i + run] == lengths[i]) ++run;
    const uint8_t l = lengths[i];
    if (l == 0 && run >= 3) {
      const size_t take = std::min<size_t>(run, 138);
      items.push_back(take >= 11 ? std::pair<uint8_t, uint8_t>{18, uint8_t(take - 11)}
                                 : std::pair<uint8_t, uint8_t>{17, uint8_t(take - 3)});
      i += take;
    } else if (l != 0 && run >= 4) {
      items.push_back({l, 0});  // the first said, then repeated
      const size_t take = std::min<size_t>(run - 1, 6);
      items.push_back({16, uint8_t(take - 3)});
      i += 1 + take;
    } else {
      items.push_back({l, 0});
      ++i;
    }
  }
  return items;
}

// One final block with codes made for its own symbols (RFC 1951, 3.2.7).
void dynamic_block(BitWriter& w, const std::vector<Token>& tokens) {
  std::vector<uint32_t> literal_counts(286, 0), distance_counts(30, 0);
  for (const Token& t : tokens) {
    if (t.distance == 0) {
      ++literal_counts[t.length_or_byte];
    } else {
      ++literal_counts[length_symbol(t.length_or_byte).code];
      ++distance_counts[distance_symbol(t.distance).code];
    }
  }
  literal_counts[kEndOfBlock] = 1;
  const auto literal_lengths = code_lengths(literal_counts, kLongestCode);
  const auto distance_lengths = code_lengths(distance_counts, kLongestCode);
  size_t literals = 286, distances = 30;
  while (literal_lengths[literals - 1] == 0) --literals;
  while (distance_lengths[distances - 1] == 0) --distances;
  std::vector<uint8_t> all(literal_lengths.begin(), literal_lengths.begin() + literals);
  all.insert(all.end(), distance_lengths.begin(), distance_lengths.begin() + distances);
  const auto items = run_length(all);
  std::vector<uint32_t> item_counts(19, 0);
  for (const auto& item : items) ++item_counts[item.first];
  const auto item_lengths = code_lengths(item_counts, kLongestLengthCode);
  size_t sent = 19;
  while (sent > 4 && item_lengths[kLengthCodeOrder[sent - 1]] == 0) --sent;

  w.bits(1, 1);  // the last block
  w.bits(2, 2);  // dynamic Huffman codes
  w.bits(static_cast<uint32_t>(literals - 257), 5);
  w.bits(static_cast<uint32_t>(distances - 1), 5);
  w.bits(static_cast<uint32_t>(sent - 4), 4);
  for (size_t k = 0; k < sent; ++k) w.bits(item_lengths[kLengthCodeOrder[k]], 3);
  const auto item_codes = canonical_codes(item_lengths);
  constexpr std::array<uint8_t, 3> kItemExtra = {2, 3, 7};  // of 16, 17, 18
  for (const auto& [symbol, extra] : items) {
    w.code(item_codes[symbol], item_lengths[symbol]);
    if (symbol >= 16) w.bits(extra, kItemExtra[symbol - 16]);
  }
  const auto literal_codes = canonical_codes(literal_lengths);
  const auto distance_codes = canonical_codes(distance_lengths);
  for (const Token& t : tokens) {
    if (t.distance == 0) {
      w.code(literal_codes[t.length_or_byte], literal_lengths[t.length_or_byte]);
      continue;
    }
    const Symbol l = length_symbol(t.length_or_byte), d = distance_symbol(t.distance);
    w.code(literal_codes[l.code], literal_lengths[l.code]);
    w.bits(l.extra, l.extra_bits);
    w.code(distance_codes[d.code], distance_lengths[d.code]);
    w.bits(d.extra, d.extra_bits);
  }
  w.code(literal_codes[kEndOfBlock], literal_lengths[kEndOfBlock]);
}

uint32_t adler32(std::span<const uint8_t> bytes) {
  uint32_t a = 1, b = 0;
  for (uint8_t c : bytes) a = (a + c) % 65521, b = (b + a) % 65521;
  return (b << 16) | a;
}

void put_be32(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>(v >> shift));
}

void put_png_chunk(std::string& out, std::string_view type, std::string_view data) {
  put_be32(out, static_cast<uint32_t>(data.size()));
  const size_t typed = out.size();
  out.append(type);
  out.append(data);
  put_be32(out, progressive::crc32(std::string_view(out).substr(typed)));
}

}  // namespace

std::string zlib_compress(std::span<const uint8_t> in) {
  BitWriter w;
  w.bytes = "\x78\x01";  // deflate, 32 KiB window, no dictionary; a multiple of 31
  dynamic_block(w, lz77(in));
  w.flush();
  put_be32(w.bytes, adler32(in));
  return std::move(w.bytes);
}

namespace {

// The image as indices into its 256 most common colours (most common first, then by value),
// each other colour mapped to the nearest of them (RGB distance); none when that nearest one
// differs from it by more than kPaletteTolerance on a channel. rgb: the palette's bytes.
struct Indexed {
  std::string rgb;
  std::vector<uint8_t> index;  // a pixel's
};
std::optional<Indexed> indexed(std::span<const uint8_t> rgb) {
  const auto colour_at = [&](size_t i) {
    return uint32_t{rgb[i]} << 16 | uint32_t{rgb[i + 1]} << 8 | rgb[i + 2];
  };
  std::vector<uint32_t> colours;
  colours.reserve(rgb.size() / 3);
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) colours.push_back(colour_at(i));
  std::sort(colours.begin(), colours.end());
  std::vector<std::pair<size_t, uint32_t>> counted;  // (count, colour)
  for (size_t i = 0; i < colours.size();) {
    size_t j = i;
    while (j < colours.size() && colours[j] == colours[i]) ++j;
    counted.push_back({j - i, colours[i]});
    i = j;
  }
  std::sort(counted.begin(), counted.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  const size_t kept = std::min<size_t>(counted.size(), 256);
  Indexed out;
  std::vector<std::pair<uint32_t, uint8_t>> slot;  // colour → index, sorted by colour
  for (size_t k = 0; k < counted.size(); ++k) {
    const uint32_t c = counted[k].second;
    if (k < kept) {
      for (int shift : {16, 8, 0}) out.rgb.push_back(static_cast<char>(c >> shift & 0xff));
      slot.push_back({c, static_cast<uint8_t>(k)});
      continue;
    }
    int best = -1, best_distance = 0, best_spread = 0;
    for (size_t p = 0; p < kept; ++p) {
      int distance = 0, spread = 0;
      for (int shift : {16, 8, 0}) {
        const int d = int(c >> shift & 0xff) - int(uint8_t(out.rgb[3 * p + (16 - shift) / 8]));
        distance += d * d, spread = std::max(spread, std::abs(d));
      }
      if (best < 0 || distance < best_distance)
        best = static_cast<int>(p), best_distance = distance, best_spread = spread;
    }
    if (best_spread > kPaletteTolerance) return std::nullopt;
    slot.push_back({c, static_cast<uint8_t>(best)});
  }
  std::sort(slot.begin(), slot.end());
  out.index.reserve(rgb.size() / 3);
  for (size_t i = 0; i + 2 < rgb.size(); i += 3)
    out.index.push_back(
        std::lower_bound(slot.begin(), slot.end(), std::pair<uint32_t, uint8_t>{colour_at(i), 0})
            ->second);
  return out;
}

// The PNG of one IDAT stream; colour type 2 (RGB) or 3 (palette, `palette` its PLTE).
std::string png_file(uint32_t width, uint32_t height, uint8_t colour_type,
                     const std::string& palette, const std::string& idat) {
  std::string header;
  put_be32(header, width);
  put_be32(header, height);
  header.push_back(8);  // bits per sample (an index, for a palette)
  header.push_back(static_cast<char>(colour_type));
  header.append(3, '\0');  // deflate, filters of method 0, no interlace
  std::string png("\x89PNG\r\n\x1a\n", 8);
  put_png_chunk(png, "IHDR", header);
  if (!palette.empty()) put_png_chunk(png, "PLTE", palette);
  put_png_chunk(png, "IDAT", idat);
  put_png_chunk(png, "IEND", {});
  return png;
}

}  // namespace

std::string encode_png(std::span<const uint8_t> rgb, uint32_t width, uint32_t height) {
  // Every row unfiltered (type 0) or every row as Sub (type 1, the difference to the pixel on the
  // left), whichever compresses smaller: flat-shaded facets repeat whole pixels, which LZ77
  // takes at distance 3 either way, and unfiltered mostly wins (crash boxes: by 13–15 %).
  // A palette image of unfiltered rows is kept when smaller still (a third of the bytes to
  // deflate: crash boxes 27–28 % smaller, docs/BENCHMARKS.md).
  const size_t stride = size_t{width} * 3;
  std::string smallest;
  for (uint8_t filter : {0, 1}) {
    std::vector<uint8_t> rows;
    rows.reserve((stride + 1) * height);
    for (uint32_t y = 0; y < height; ++y) {
      rows.push_back(filter);
      const uint8_t* row = rgb.data() + y * stride;
      for (size_t x = 0; x < stride; ++x)
        rows.push_back(static_cast<uint8_t>(row[x] - (filter == 1 && x >= 3 ? row[x - 3] : 0)));
    }
    std::string z = zlib_compress(rows);
    if (smallest.empty() || z.size() < smallest.size()) smallest = std::move(z);
  }
  std::string png = png_file(width, height, 2, {}, smallest);
  if (const std::optional<Indexed> image = indexed(rgb)) {
    std::vector<uint8_t> rows;
    rows.reserve((size_t{width} + 1) * height);
    for (uint32_t y = 0; y < height; ++y) {
      rows.push_back(0);
      rows.insert(rows.end(), image->index.begin() + size_t{y} * width,
                  image->index.begin() + size_t{y + 1} * width);
    }
    std::string indexed_png = png_file(width, height, 3, image->rgb, zlib_compress(rows));
    if (indexed_png.size() < png.size()) png = std::move(indexed_png);
  }
  return png;
}

}  // namespace dynpm::pipeline

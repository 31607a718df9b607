// The thumbnail (render_thumbnail(), the THMB chunk, docs/FORMAT.md "Thumbnail: THMB"): the PNG's
// zlib stream inflates with zlib itself to the bytes it was made from; the picture of the real
// crash box shows the model over a sensible part of the frame, shaded; the chunk goes before END
// and leaves every other byte of the file as it was, a second one replaces the first, both
// readers of the model skip it; dynpm build stores one, drawn from its own records and positions,
// and dynpm thumbnail writes the same PNG.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <string>

#include "dynpm/io.h"
#include "dynpm/pipeline.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "pipeline/png.h"

namespace dynpm {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

std::string inflated(const std::string& stream, size_t size) {
  std::string out(size + 1, '\0');
  uLongf length = static_cast<uLongf>(out.size());
  const int r = uncompress(reinterpret_cast<Bytef*>(out.data()), &length,
                           reinterpret_cast<const Bytef*>(stream.data()), stream.size());
  EXPECT_EQ(r, Z_OK);
  out.resize(length);
  return out;
}

TEST(Thumbnail, ZlibStreamInflatesWithZlib) {
  std::mt19937 random(7);
  std::vector<std::vector<uint8_t>> inputs = {{}, {42}, std::vector<uint8_t>(100000, 0)};
  std::vector<uint8_t> mixed;
  for (int k = 0; k < 3000; ++k) {
    const uint8_t b = static_cast<uint8_t>(random() % 7);
    const size_t run = random() % 300;  // runs longer than deflate's longest match
    mixed.insert(mixed.end(), run, b);
    for (int i = 0; i < 5; ++i) mixed.push_back(static_cast<uint8_t>(random()));
  }
  inputs.push_back(mixed);
  std::vector<uint8_t> noise(70000);  // beyond the 32 KiB window, nothing to match
  for (uint8_t& b : noise) b = static_cast<uint8_t>(random());
  inputs.push_back(noise);
  // Byte k 2^k times, shuffled: its Huffman code (and the code of its code lengths) would be
  // longer than deflate allows, so both are limited.
  std::vector<uint8_t> skewed;
  for (int k = 0; k < 18; ++k)
    skewed.insert(skewed.end(), size_t{1} << k, static_cast<uint8_t>(k * 13));
  std::shuffle(skewed.begin(), skewed.end(), random);
  inputs.push_back(skewed);
  for (const auto& in : inputs) {
    const std::string z = pipeline::zlib_compress(in);
    EXPECT_EQ(inflated(z, in.size()), std::string(in.begin(), in.end())) << in.size() << " bytes";
  }
  EXPECT_LT(pipeline::zlib_compress(inputs[2]).size(), 1000u);  // runs compress
}

// A decoded PNG: 8-bit RGB with filter types 0 or 1, or 8-bit palette indices with filter type
// 0 (those encode_png writes), as RGB.
struct Picture {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgb;
};
Picture decode_png(const std::string& png) {
  Picture p;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](size_t at) {
    return uint32_t(uint8_t(png[at])) << 24 | uint32_t(uint8_t(png[at + 1])) << 16 |
           uint32_t(uint8_t(png[at + 2])) << 8 | uint32_t(uint8_t(png[at + 3]));
  };
  std::string idat, palette;
  char colour_type = 0;
  for (size_t at = 8; at + 12 <= png.size();) {
    const uint32_t length = be32(at);
    const std::string type = png.substr(at + 4, 4), data = png.substr(at + 8, length);
    EXPECT_EQ(be32(at + 8 + length),
              crc32(0, reinterpret_cast<const Bytef*>(png.data() + at + 4), length + 4))
        << type;
    if (type == "IHDR") {
      p.width = be32(at + 8), p.height = be32(at + 12);
      EXPECT_EQ(data[8], 8);  // bits
      colour_type = data[9];
      EXPECT_TRUE(colour_type == 2 || colour_type == 3) << int(colour_type);  // RGB, palette
    }
    if (type == "PLTE") palette = data;
    if (type == "IDAT") idat += data;
    at += 12 + length;
  }
  if (colour_type == 3) {
    EXPECT_TRUE(palette.size() % 3 == 0 && palette.size() > 0 && palette.size() <= 768);
    const std::string rows = inflated(idat, (size_t{p.width} + 1) * p.height);
    EXPECT_EQ(rows.size(), (size_t{p.width} + 1) * p.height);
    for (size_t i = 0; i < rows.size(); ++i) {
      if (i % (p.width + 1) == 0) {
        EXPECT_EQ(rows[i], 0) << "filter of row " << i / (p.width + 1);
        continue;
      }
      const size_t k = 3 * uint8_t(rows[i]);
      EXPECT_LT(k, palette.size());
      for (int c = 0; c < 3; ++c) p.rgb.push_back(k < palette.size() ? uint8_t(palette[k + c]) : 0);
    }
    return p;
  }
  const size_t stride = size_t{p.width} * 3;
  const std::string rows = inflated(idat, (stride + 1) * p.height);
  EXPECT_EQ(rows.size(), (stride + 1) * p.height);
  for (uint32_t y = 0; y < p.height && rows.size() == (stride + 1) * p.height; ++y) {
    const uint8_t filter = uint8_t(rows[y * (stride + 1)]);
    EXPECT_LE(filter, 1);
    for (size_t x = 0; x < stride; ++x) {
      const uint8_t left = filter == 1 && x >= 3 ? p.rgb[y * stride + x - 3] : 0;
      p.rgb.push_back(static_cast<uint8_t>(uint8_t(rows[y * (stride + 1) + 1 + x]) + left));
    }
  }
  return p;
}

// encode_png keeps a picture's colours: exactly when 256 or fewer (as a palette, smaller) or
// when they are many and far apart (RGB); a few extra colours near the 256 most common (blended
// edge pixels) become the nearest of them, within 24 a channel.
TEST(Thumbnail, PngKeepsTheColours) {
  const uint32_t w = 64, h = 48;
  std::mt19937 random(11);
  auto image = [&](int colours, int extra) {  // pixels of `colours` colours, `extra` shaded off
    std::vector<uint8_t> rgb(size_t{w} * h * 3);
    for (size_t i = 0; i < size_t{w} * h; ++i) {
      const uint32_t c = random() % colours;
      for (int k = 0; k < 3; ++k) rgb[3 * i + k] = static_cast<uint8_t>((c * (37 + 60 * k)) % 231);
    }
    for (int e = 0; e < extra; ++e)  // a shade near a palette colour
      rgb[3 * (random() % (size_t{w} * h)) + e % 3] += static_cast<uint8_t>(1 + e % 20);
    return rgb;
  };
  auto max_difference = [](const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    int most = 0;
    for (size_t i = 0; i < a.size(); ++i) most = std::max(most, std::abs(int(a[i]) - int(b[i])));
    return most;
  };
  const std::vector<uint8_t> few = image(150, 0), near = image(190, 120);
  std::vector<uint8_t> many(size_t{w} * h * 3);
  for (auto& b : many) b = static_cast<uint8_t>(random());
  for (const std::vector<uint8_t>* rgb :
       {&few, &near, static_cast<const std::vector<uint8_t>*>(&many)}) {
    const std::string png = pipeline::encode_png(*rgb, w, h);
    const Picture p = decode_png(png);
    ASSERT_EQ(p.rgb.size(), rgb->size());
    const bool palette = png.find("PLTE") != std::string::npos;
    if (rgb == &many) {
      EXPECT_FALSE(palette);
      EXPECT_EQ(p.rgb, *rgb);
    } else {
      EXPECT_TRUE(palette);
      EXPECT_LE(max_difference(p.rgb, *rgb), rgb == &few ? 0 : 24);
    }
  }
}

// The chunk tags of a .dpm, in order.
std::vector<std::string> tags(const std::string& dpm) {
  std::vector<std::string> out;
  for (size_t at = 12; at + 24 <= dpm.size();) {
    uint32_t stored = 0;
    std::memcpy(&stored, dpm.data() + at + 8, 4);
    out.push_back(dpm.substr(at, 4));
    at += 24 + stored;
  }
  return out;
}

std::string crash_box_dpm(const test::TempDir& dir, const std::string& flags) {
  const std::string frd = dir.file("s.frd"), out = dir.file("s.dpm");
  const std::string command = "zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > " +
                              frd + " && " + DYNPM_CLI + " build " + frd + " " + flags +
                              " --quiet -o " + out + " > /dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0);
  return out;
}

TEST(Thumbnail, TheCrashBoxPictureShowsTheModelShaded) {
  test::TempDir dir;
  const std::string dpm = crash_box_dpm(dir, "");
  auto png = read_dpm_thumbnail(dpm);
  ASSERT_TRUE(png.ok()) << png.message();
  ASSERT_TRUE(png->has_value());
  const Picture p = decode_png(**png);
  ASSERT_EQ(p.width, 256u);
  ASSERT_EQ(p.height, 192u);
  ASSERT_EQ(p.rgb.size(), 256u * 192 * 3);
  size_t model = 0;
  std::set<uint32_t> colours;
  uint32_t x0 = p.width, x1 = 0, y0 = p.height, y1 = 0;
  const auto pixel = [&](uint32_t x, uint32_t y) { return &p.rgb[(size_t(y) * p.width + x) * 3]; };
  const auto background = [](const uint8_t* c) {
    return c[0] == 0xee && c[1] == 0xf0 && c[2] == 0xf3;
  };
  for (uint32_t y = 0; y < p.height; ++y)
    for (uint32_t x = 0; x < p.width; ++x) {
      const uint8_t* c = pixel(x, y);
      if (background(c)) continue;
      ++model;
      colours.insert(uint32_t(c[0]) << 16 | uint32_t(c[1]) << 8 | c[2]);
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  const double covered = double(model) / (p.width * p.height);
  EXPECT_GT(covered, 0.1);
  EXPECT_LT(covered, 0.9);
  // Fitted with a margin: the model spans most of the frame one way, and touches no edge.
  EXPECT_TRUE(x1 - x0 > 0.8 * p.width || y1 - y0 > 0.8 * p.height)
      << x0 << " " << x1 << " " << y0 << " " << y1;
  EXPECT_GT(x0, 0u);
  EXPECT_GT(y0, 0u);
  EXPECT_LT(x1, p.width - 1);
  EXPECT_LT(y1, p.height - 1);
  EXPECT_GT(colours.size(), 20u);  // facets shaded differently (and their antialiased edges)
  // Inside the facets (a pixel whose 3 × 3 block is one colour), the part's colour in at most
  // 17 shades (16 steps of the headlight), and in several.
  std::set<uint32_t> inside;
  for (uint32_t y = 1; y + 1 < p.height; ++y)
    for (uint32_t x = 1; x + 1 < p.width; ++x) {
      const uint8_t* c = pixel(x, y);
      bool flat = !background(c);
      for (int dy = -1; dy <= 1 && flat; ++dy)
        for (int dx = -1; dx <= 1 && flat; ++dx)
          flat = std::memcmp(c, pixel(x + dx, y + dy), 3) == 0;
      if (flat) inside.insert(uint32_t(c[0]) << 16 | uint32_t(c[1]) << 8 | c[2]);
    }
  EXPECT_LE(inside.size(), 17u);
  EXPECT_GE(inside.size(), 5u);
  EXPECT_LT((*png)->size(), 40000u);

  // dynpm thumbnail -o draws the same picture from the file.
  const std::string out = dir.file("t.png");
  ASSERT_EQ(std::system((std::string(DYNPM_CLI) + " thumbnail " + dpm + " -q -o " + out).c_str()),
            0);
  EXPECT_EQ(slurp(out), **png);
}

TEST(Thumbnail, TheChunkGoesBeforeEndAndChangesNothingElse) {
  test::TempDir dir;
  const std::string plain = slurp(crash_box_dpm(dir, "--no-thumbnail"));
  const std::string built = slurp(crash_box_dpm(dir, ""));
  std::vector<std::string> expected = tags(plain);
  EXPECT_EQ(expected.back(), "END ");
  expected.insert(expected.end() - 1, "THMB");
  EXPECT_EQ(tags(built), expected);
  // The model's bytes are the ones a build without the thumbnail writes.
  EXPECT_EQ(built.substr(0, plain.size() - 24), plain.substr(0, plain.size() - 24));
  EXPECT_EQ(built.substr(built.size() - 24), plain.substr(plain.size() - 24));
  // Added again, it replaces the first.
  auto again = with_thumbnail(built, "picture", "again");
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(tags(*again), expected);
  EXPECT_EQ(again->size(), plain.size() + 24 + 7);
  // Both files read to the same model (the reader skips the chunk as an unknown optional one).
  auto a = decode_dpm(plain, "plain"), b = decode_dpm(*again, "again");
  ASSERT_TRUE(a.ok() && b.ok()) << b.message();
  EXPECT_TRUE(b->complete);
  EXPECT_EQ(a->positions, b->positions);
  EXPECT_EQ(a->parent, b->parent);
  // dynpm thumbnail stores it in a file built without one: the build's bytes.
  const std::string path = dir.file("old.dpm");
  std::ofstream(path, std::ios::binary) << plain;
  ASSERT_EQ(std::system((std::string(DYNPM_CLI) + " thumbnail -q " + path).c_str()), 0);
  EXPECT_TRUE(slurp(path) == built);
  // A prefix of a file (no END) gets none, and says why.
  auto partial = with_thumbnail(plain.substr(0, plain.size() - 24), "x", "prefix.dpm");
  ASSERT_FALSE(partial.ok());
  EXPECT_NE(partial.message().find("prefix.dpm: byte"), std::string::npos) << partial.message();
  // read_dpm_thumbnail: none in the plain file; a damaged one is an error naming the chunk.
  std::ofstream(path, std::ios::binary) << plain;
  EXPECT_FALSE(read_dpm_thumbnail(path).value().has_value());
  std::string damaged = *again;
  damaged[damaged.size() - 24 - 3] ^= 1;
  std::ofstream(path, std::ios::binary) << damaged;
  auto bad = read_dpm_thumbnail(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("THMB chunk: wrong checksum"), std::string::npos) << bad.message();
}

// build_dpm() draws the thumbnail from its own records and positions: the same PNG as
// add_thumbnail() draws from the bytes built without one, at the default level, at the base
// mesh alone, at every vertex, for an animation (its first and last steps) and a static model.
TEST(Thumbnail, TheBuildDrawsWhatAReaderOfItsFileDraws) {
  test::TempDir dir;
  const std::string frd = dir.file("s.frd");
  ASSERT_EQ(
      std::system(
          ("zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > " + frd).c_str()),
      0);
  for (const std::string& input : {frd, test::shared_data() + "/meshes/bunny.obj"}) {
    auto stream = open_input(std::vector<std::string>{input});
    ASSERT_TRUE(stream.ok()) << stream.message();
    BuildOptions options;
    options.simplify.key_steps = {0, stream->frames->step_count() - 1};
    auto plain = build_dpm(stream->topology, *stream->frames, options);
    ASSERT_TRUE(plain.ok()) << plain.message();
    for (const double ratio : {0.05, 0.0, 1.0}) {
      const ThumbnailOptions picture{.ratio = ratio};
      options.thumbnail = picture;
      auto built = build_dpm(stream->topology, *stream->frames, options);
      ASSERT_TRUE(built.ok()) << built.message();
      auto from_file = add_thumbnail(plain->bytes, "plain", picture);
      ASSERT_TRUE(from_file.ok()) << from_file.message();
      EXPECT_TRUE(built->bytes == *from_file) << input << " at " << ratio;
    }
  }
}

}  // namespace
}  // namespace dynpm

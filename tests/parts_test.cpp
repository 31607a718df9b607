// Part names (docs/FORMAT.md "Part names: PART"): made safe where they enter (clean_part_name),
// read from the inputs that have them — LS-DYNA d3plot part titles (third-party files), an
// Exodus II file's block names (written by scripts/sample/make_parts.py with netCDF4), OBJ `g`
// and `o` names — carried through a build into the .dpm and back, a file without PART read by id,
// and a damaged PART refused at its byte.
#include <gtest/gtest.h>

#include <fstream>
#include <tuple>

#include "dpm_chunks.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

using test::chunk;
using test::chunks_of;
using test::expect_refused_at;
using test::put;
using test::with_payload;

TEST(PartNames, CleanedWhereTheyEnter) {
  EXPECT_EQ(clean_part_name("  Profil_Shells     "), "Profil_Shells");
  EXPECT_EQ(clean_part_name(std::string("B-pillar\0\0\0", 11)), "B-pillar");
  EXPECT_EQ(clean_part_name("Längsträger — links"), "Längsträger — links");
  // A terminal escape and a lone continuation byte become U+FFFD; nothing is dropped silently.
  EXPECT_EQ(clean_part_name("red\x1b[31m"), "red\xef\xbf\xbd[31m");
  EXPECT_EQ(clean_part_name("a\x80z"), "a\xef\xbf\xbdz");
  EXPECT_EQ(clean_part_name("\xc0\xaf"), "\xef\xbf\xbd\xef\xbf\xbd");  // overlong '/'
  EXPECT_EQ(clean_part_name("\xed\xa0\x80"), "\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd");  // surrogate
  EXPECT_EQ(clean_part_name(" \t\0 "), "");
  // Cut to 255 bytes at a character boundary: 200 × 'ä' (2 bytes) keeps 127 of them.
  std::string long_name;
  for (int i = 0; i < 200; ++i) long_name += "ä";
  EXPECT_EQ(clean_part_name(long_name).size(), 254u);
  for (const std::string raw : {"x\x01y", " lead", "tail ", "ok", "\xf4\x90\x80\x80", "\xc2\x85"})
    EXPECT_TRUE(is_clean_part_name(clean_part_name(raw)) || clean_part_name(raw).empty()) << raw;
  EXPECT_FALSE(is_clean_part_name(""));
  EXPECT_FALSE(is_clean_part_name(" a"));
  EXPECT_FALSE(is_clean_part_name("a\x7f"));
  EXPECT_FALSE(is_clean_part_name("\xc2\x9b"));  // C1 CSI
  EXPECT_FALSE(is_clean_part_name(std::string(256, 'a')));
  EXPECT_TRUE(is_clean_part_name(std::string(255, 'a')));
}

TEST(PartNames, ObjGroupsAndObjectsNameTheirParts) {
  test::TempDir dir;
  const std::string path = dir.file("named.obj");
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                         "o Door outer\nf 1 2 3 4\ng part_7\nf 2 5 6\n"
                         "g red\x1b[0m\nf 2 6 3\n";
  auto mesh = read_mesh(path);
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  const Topology& t = mesh->topology;
  ASSERT_EQ(t.part_ids.size(), 3u);
  EXPECT_EQ(t.part_ids[1], 7);  // a number names an id, not a name
  EXPECT_EQ(t.part_name(t.part_ids[0]), "Door outer");
  EXPECT_EQ(t.part_name(7), "");
  EXPECT_EQ(t.part_name(t.part_ids[2]), "red\xef\xbf\xbd[0m");
  EXPECT_EQ(t.part_names.size(), 2u);
}

TEST(PartNames, D3plotPartTitles) {
  // Two third-party families, each one shell part with its title padded to 72 bytes:
  // qd-cae-python's (part 1, "Zugprobe") and open-lasso-python's (part 1000000, a user id).
  for (const auto& [file, id, title] :
       {std::tuple{"qd_d3plot", 1, "Zugprobe"},
        std::tuple{"lasso_d3plot_node_temperature_d3plot", 1000000, "Profil_Shells"}}) {
    auto stream =
        open_input(std::vector<std::string>{test::shared_data() + "/external/d3plot/" + file});
    ASSERT_TRUE(stream.ok()) << stream.message();
    const Topology& t = stream->topology;
    EXPECT_EQ(t.parts(), std::vector<int32_t>{id});
    EXPECT_EQ(t.part_names, (std::vector<PartName>{{id, title}})) << file;
  }
}

// The hat rail as six named Exodus blocks (make_parts.py), read, built and read back from .dpm.
struct NamedRail {
  test::TempDir dir;
  std::string exodus;
};

const std::vector<PartName> kRailParts = {{101, "Hat top"},     {102, "Hat top — hole patch"},
                                          {201, "Wall left"},   {202, "Wall right"},
                                          {301, "Flange left"}, {302, "Flange right"}};

bool make_named_rail(NamedRail& rail, const std::string& python) {
  auto frames = expand_inputs(std::vector<std::string>{test::sample_dir() + "/frame_00*.obj"});
  EXPECT_TRUE(frames.ok());
  rail.exodus = rail.dir.file("rail-parts.e");
  std::string command =
      python + " " + test::source_dir() + "/scripts/sample/make_parts.py " + rail.exodus;
  for (const std::string& f : *frames) command += " " + f;
  const auto run = test::run_command(command);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return run.exit_code == 0;
}

TEST(PartNames, ExodusBlockNamesThroughTheDpm) {
  const std::string python = test::python_with("netCDF4, numpy");
  DYNPM_REQUIRE_PYTHON(python, "python3-netcdf4 with python3-numpy");
  NamedRail rail;
  ASSERT_TRUE(make_named_rail(rail, python));
  auto stream = open_input(std::vector<std::string>{rail.exodus});
  ASSERT_TRUE(stream.ok()) << stream.message();
  EXPECT_EQ(stream->topology.part_names, kRailParts);
  EXPECT_EQ(stream->topology.parts().size(), kRailParts.size());
  auto animation = load_all_steps(std::move(stream).value());
  ASSERT_TRUE(animation.ok()) << animation.message();

  auto pm = build_progressive_mesh(animation->topology, animation->frames, BuildOptions{});
  ASSERT_TRUE(pm.ok()) << pm.message();
  const std::string bytes = encode_dpm(*pm).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_EQ(chunks[1].first, "PART");
  auto back = decode_dpm(bytes, "rail.dpm");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->part_names, kRailParts);
  Navigator nav(*back);
  nav.set_level(back->split_count());
  EXPECT_EQ(nav.topology().part_name(202), "Wall right");
  // Every face keeps its part: the full mesh's faces per part are the input's.
  for (const PartName& p : kRailParts)
    EXPECT_EQ(
        std::count(back->part_ids.begin(), back->part_ids.end(), p.id),
        std::count(animation->topology.part_ids.begin(), animation->topology.part_ids.end(), p.id))
        << p.name;

  // Without PART (an older writer): the same mesh, parts by id only.
  const size_t part = chunks[1].second, base = chunks[2].second;
  auto plain = decode_dpm(bytes.substr(0, part) + bytes.substr(base), "plain.dpm");
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_TRUE(plain->part_names.empty());
  EXPECT_EQ(plain->part_ids, back->part_ids);
  EXPECT_EQ(plain->split_count(), back->split_count());

  // Damage, each refused at the payload's first byte (u32 count, then i32 id, u16 length, name).
  const std::string payload = bytes.substr(part + 24, base - part - 24);
  auto refuse = [&](const std::string& changed, const std::string& what) {
    expect_refused_at(with_payload(bytes, part, changed), part + 24, what);
  };
  refuse(put<uint32_t>(payload, 0, 0), "part count is not valid");
  refuse(put<uint32_t>(payload, 0, 1000), "part count is not valid");
  refuse(put<int32_t>(payload, 4, 500), "ascending ids");
  refuse(put<uint16_t>(payload, 8, 0), "is not 1 to 255 bytes");
  refuse(put<uint8_t>(payload, 10, 0x1b), "control characters");
  refuse(put<uint8_t>(payload, 10, 0xff), "UTF-8");
  refuse(put<uint8_t>(payload, 10, ' '), "blanks at its ends");
  refuse(payload + "x", "unexpected bytes after the part names");
  refuse(payload.substr(0, payload.size() - 1), "cut short");
  // PART after BASE, or before FDEF, is out of order; a prefix ending inside PART has no level.
  expect_refused_at(bytes.substr(0, part) + bytes.substr(base, chunks[3].second - base) +
                        bytes.substr(part, base - part) + bytes.substr(chunks[3].second),
                    part + (chunks[3].second - base), "unexpected chunk 'PART'");
  expect_refused_at(bytes.substr(0, part + 30), part, "ends before the base mesh is complete");
}

}  // namespace
}  // namespace dynpm

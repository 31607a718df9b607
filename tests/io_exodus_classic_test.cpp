// Exodus II in netCDF's classic formats read without netCDF (io/exodus_classic.h): every float
// and double variable of VTK's classic test files, whole and in hyperslabs, must come out as
// netCDF's own nc_get_vara_double() gives it, bit for bit; a hyperslab outside a variable is an
// error naming the file and the variable; and the steps and fields of a classic file read on
// several threads at once are the ones read on one.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <cstring>
#include <filesystem>

#include "dynpm/io.h"
#include "fixtures.h"
#include "io/exodus_classic.h"
#include "reading.h"

namespace dynpm {
namespace {

using io::ClassicLayout;
using io::ClassicValues;

const char* const kClassicFiles[] = {"vtkdata_box-noglom.ex2",   "vtkdata_coarseGrid.e",
                                     "vtkdata_disk_out_ref.ex2", "vtkdata_edgeFaceElem.exii",
                                     "vtkdata_mesh_fs8.exo",     "vtkdata_mug.e"};

std::string exodus_file(const std::string& name) {
  return test::shared_data() + "/external/exodus/" + name;
}

Result<ClassicLayout> layout_of(const std::string& path) {
  const char version = io::classic_version(path);
  if (version == 0) return Status::error(path + ": not a classic netCDF file");
  return io::check_classic_header(path, std::filesystem::file_size(path), version);
}

// The same doubles, bit for bit (NaN fill values included).
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

TEST(ExodusClassic, EveryFloatAndDoubleVariableIsNetcdfsBitForBit) {
  size_t variables = 0, record_variables = 0, slabs = 0;
  for (const char* name : kClassicFiles) {
    SCOPED_TRACE(name);
    const std::string path = exodus_file(name);
    auto layout = layout_of(path);
    ASSERT_TRUE(layout.ok()) << layout.message();
    auto values = ClassicValues::open(path, *layout);
    ASSERT_TRUE(values.has_value());
    int id = -1;
    ASSERT_EQ(nc_open(path.c_str(), NC_NOWRITE, &id), NC_NOERR);
    int count = 0;
    ASSERT_EQ(nc_inq_nvars(id, &count), NC_NOERR);
    ASSERT_EQ(static_cast<size_t>(count), layout->variables.size());
    for (int var = 0; var < count; ++var) {
      nc_type type;
      int rank = 0;
      ASSERT_EQ(nc_inq_vartype(id, var, &type), NC_NOERR);
      EXPECT_EQ(values->reads(var), type == NC_FLOAT || type == NC_DOUBLE) << var;
      if (!values->reads(var)) continue;
      ASSERT_EQ(nc_inq_varndims(id, var, &rank), NC_NOERR);
      std::vector<int> dims(static_cast<size_t>(rank));
      nc_inq_vardimid(id, var, dims.data());
      std::vector<size_t> lengths(dims.size());
      for (size_t d = 0; d < dims.size(); ++d) nc_inq_dimlen(id, dims[d], &lengths[d]);
      // The whole variable, then a hyperslab from a third of each dimension to two thirds.
      std::vector<size_t> start(lengths.size(), 0), mid_start(lengths.size()),
          mid_count(lengths.size());
      for (size_t d = 0; d < lengths.size(); ++d) {
        mid_start[d] = lengths[d] / 3;
        mid_count[d] = lengths[d] == 0 ? 0 : std::max<size_t>(1, lengths[d] / 3);
      }
      for (const auto& [from, counts] : {std::pair{start, lengths}, {mid_start, mid_count}}) {
        size_t total = 1;
        for (size_t c : counts) total *= c;
        std::vector<double> expected(total), got;
        if (total > 0) {
          ASSERT_EQ(nc_get_vara_double(id, var, from.data(), counts.data(), expected.data()),
                    NC_NOERR);
        }
        ASSERT_TRUE(values->read(var, "v", from, counts, got).ok()) << var;
        EXPECT_TRUE(same_bits(got, expected)) << "variable " << var;
        slabs += total > 0;
      }
      ++variables;
      record_variables += layout->variables[static_cast<size_t>(var)].record;
    }
    nc_close(id);
  }
  // Coordinates, times, nodal and element variables of six files, in both formats' layouts.
  EXPECT_GE(variables, 40u);
  EXPECT_GE(record_variables, 15u);
  EXPECT_GE(slabs, 60u);
}

TEST(ExodusClassic, AHyperslabOutsideTheVariableIsAnError) {
  const std::string path = exodus_file("vtkdata_mug.e");
  auto layout = layout_of(path);
  ASSERT_TRUE(layout.ok()) << layout.message();
  auto values = ClassicValues::open(path, *layout);
  ASSERT_TRUE(values.has_value());
  // The first record variable of two dimensions or more: one record past the last, a count
  // past the end, too few indices.
  int var = -1;
  for (size_t v = 0; v < layout->variables.size() && var < 0; ++v)
    if (layout->variables[v].record && !layout->variables[v].lengths.empty() &&
        values->reads(static_cast<int>(v)))
      var = static_cast<int>(v);
  ASSERT_GE(var, 0);
  const ClassicLayout::Variable& v = layout->variables[static_cast<size_t>(var)];
  std::vector<size_t> start(v.lengths.size() + 1, 0), count(v.lengths.size() + 1, 1);
  start[0] = layout->records;
  std::vector<double> out;
  const Status past = values->read(var, "the variable", start, count, out);
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.message().find("vtkdata_mug.e: the variable: values 21"), std::string::npos)
      << past.message();
  start[0] = 0, count[0] = layout->records + 1;
  EXPECT_FALSE(values->read(var, "the variable", start, count, out).ok());
  const std::vector<size_t> one{0}, one_count{1};
  EXPECT_FALSE(values->read(var, "the variable", one, one_count, out).ok());
}

// read_field() and read_step() of a classic file on several threads at once give what they
// give on one (the source says it allows it: for_each_step() then reads steps in parallel).
TEST(ExodusClassic, StepsAndFieldsReadOnSeveralThreadsAreTheSame) {
  auto stream = open_input(std::vector<std::string>{exodus_file("vtkdata_mug.e")});
  ASSERT_TRUE(stream.ok()) << stream.message();
  ASSERT_EQ(stream->frames->step_count(), 21u);
  ASSERT_EQ(stream->frames->fields().size(), 3u);  // two nodal, one element
  test::expect_parallel_reads_agree(*stream);
}

}  // namespace
}  // namespace dynpm

// Exodus II files in netCDF's classic formats: recognised, and their header checked before
// netCDF's reader sees them (exodus.cpp reads them; exodus_classic.cpp says why and how).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dynpm/core.h"

namespace dynpm::io {

// The classic format's version byte (1, 2 or 5) if the file starts like one, else 0.
char classic_version(const std::string& path);

// Where a classic file keeps its variables' values (the header's var_list), so that they can be
// read without netCDF, whose C library is not safe on several threads at once.
struct ClassicLayout {
  struct Variable {
    uint64_t begin = 0;             // the first value's byte (record 0's, for a record variable)
    int type = 0;                   // nc_type
    bool record = false;            // its first dimension is the record (time) dimension
    std::vector<uint64_t> lengths;  // its other dimensions' lengths
  };
  std::vector<Variable> variables;  // by netCDF variable id: the header's order
  uint64_t records = 0;             // numrecs
  uint64_t record_size = 0;         // the bytes from one record of a variable to the next
  bool streaming = false;           // numrecs not yet written (-1): the records are not counted
};

// Every count and length of the classic header checked against the bytes left in the file, and
// every byte of data the header describes present; the layout, or an error naming the byte.
Result<ClassicLayout> check_classic_header(const std::string& path, uint64_t file_size,
                                           char version);

// Values of float and double variables read straight from a classic file with pread(), on any
// number of threads at once; converted to double as netCDF's nc_get_vara_double() converts them.
class ClassicValues {
 public:
  // Nullopt when the file cannot be opened or its records are not counted (streaming).
  static std::optional<ClassicValues> open(const std::string& path, ClassicLayout layout);
  ClassicValues(ClassicValues&& other) noexcept;
  ClassicValues& operator=(ClassicValues&&) = delete;
  ClassicValues(const ClassicValues&) = delete;
  ~ClassicValues();

  // True for a float or double variable, which read() reads.
  bool reads(int var) const;
  // The hyperslab [start, start + count) of variable `var` (the record index first, for a record
  // variable), row-major into `values`; an error naming the file and `name` when it lies
  // outside the variable or the file.
  Status read(int var, const std::string& name, std::span<const size_t> start,
              std::span<const size_t> count, std::vector<double>& values) const;

 private:
  ClassicValues(std::string path, int fd, ClassicLayout layout);
  std::string path_;
  int fd_ = -1;
  ClassicLayout layout_;
};

}  // namespace dynpm::io

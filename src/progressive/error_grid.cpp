// The split errors' grid (docs/FORMAT.md "Split records"; split_records_coding.h states it), and
// prepare_split_records(), which puts a mesh's errors on it before they are coded.
#include <algorithm>
#include <cmath>
#include <limits>

#include "split_records_coding.h"  // the grid's constants and these functions' declarations

namespace dynpm::progressive {

double error_reference(double base_error) {
  double p = 1;
  // Above 2^1023 no power of two is ≥ base_error, and the loops below never ended (both readers
  // hung on such a HEAD: docs/RELIABILITY.md finding 8); the readers refuse it first.
  if (!(base_error > 0 && base_error <= kMaxBaseError)) return p;
  while (p < base_error) p *= 2;
  while (p / 2 >= base_error) p /= 2;
  return p;
}

float error_of_code(uint32_t code, double reference) {
  if (code == 0) return 0;
  const uint32_t k = code - 1;
  const double mantissa = reference * double(kErrorStepsPerOctave + k % kErrorStepsPerOctave);
  return static_cast<float>(std::ldexp(mantissa, int(k / kErrorStepsPerOctave) - 44));
}

uint32_t error_code_at_least(double e, double reference) {
  uint32_t lo = 0, hi = kTopErrorCode;  // the answer is in [lo, hi]
  while (lo < hi) {
    const uint32_t mid = (lo + hi) / 2;
    if (double(error_of_code(mid, reference)) >= e)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

}  // namespace dynpm::progressive

namespace dynpm {

void prepare_split_records(ProgressiveMesh& mesh) {
  const uint32_t n = mesh.split_count();
  for (uint32_t i = n; i-- > 1;) mesh.error[i - 1] = std::max(mesh.error[i - 1], mesh.error[i]);
  if (n > 0 && mesh.base_error < mesh.error[0]) mesh.base_error = mesh.error[0];
  const double p = progressive::error_reference(mesh.base_error);
  mesh.base_error =
      progressive::error_of_code(progressive::error_code_at_least(mesh.base_error, p), p);
  // Levels inside an error band share one error: each distinct error is searched for once (a
  // dozen ldexp() a search, a million splits).
  float before = std::numeric_limits<float>::quiet_NaN(), coded = 0;
  for (float& e : mesh.error) {
    if (!(e == before))
      before = e, coded = progressive::error_of_code(progressive::error_code_at_least(e, p), p);
    e = coded;
  }
  for (uint32_t i = 0; i < n; ++i)
    std::sort(mesh.moved_faces.begin() + mesh.moved_start[i],
              mesh.moved_faces.begin() + mesh.moved_start[i + 1]);
}

}  // namespace dynpm

// The verbs of the dynpm command. Each takes the arguments after the verb and returns the
// process exit code: 0 success, 1 bad input or failed work, 2 bad usage.
#pragma once

#include <span>

namespace dynpm::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInvalidMesh = 3;  // read fine, but validate() found errors

int run_info(std::span<char* const> arguments);
int run_convert(std::span<char* const> arguments);
int run_hausdorff(std::span<char* const> arguments);
int run_simplify(std::span<char* const> arguments);
int run_build(std::span<char* const> arguments);
int run_extract(std::span<char* const> arguments);
int run_eval(std::span<char* const> arguments);
int run_view(std::span<char* const> arguments);
int run_batch(std::span<char* const> arguments);
int run_catalogue(std::span<char* const> arguments);
int run_serve(std::span<char* const> arguments);
int run_thumbnail(std::span<char* const> arguments);

}  // namespace dynpm::cli

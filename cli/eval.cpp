// dynpm eval — being written (issues 4, 6, 8).
#include <iostream>

#include "commands.h"

namespace dynpm::cli {

int run_eval(std::span<char* const> /*arguments*/) {
  std::cerr << "dynpm eval: not available yet\n";
  return kExitFailure;
}

}  // namespace dynpm::cli

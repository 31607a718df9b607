// dynpm view — being written (issues 4, 6, 8).
#include <iostream>

#include "commands.h"

namespace dynpm::cli {

int run_view(std::span<char* const> /*arguments*/) {
  std::cerr << "dynpm view: not available yet\n";
  return kExitFailure;
}

}  // namespace dynpm::cli

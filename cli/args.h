// Command-line flags for one verb: "--name value", "--name=value", "-o value", boolean
// "--flag", and positional arguments; "--" ends the flags. Unknown flags are errors.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

struct FlagSpec {
  std::string name;        // "--output"
  std::string short_name;  // "-o" or empty
  bool takes_value = false;
  std::string value_name;  // shown in help: "FILE"
  std::string help;
};

struct VerbSpec {
  std::string name;
  std::string usage;        // "dynpm info INPUT... [--json]"
  std::string description;  // a few lines
  std::vector<FlagSpec> flags;
};

class Args {
 public:
  std::vector<std::string> positional;

  bool has(const std::string& name) const { return flags_.count(name) != 0; }
  std::optional<std::string> value(const std::string& name) const;  // the last one given
  // Every value of a repeatable flag (--field A --field B), in the order given.
  std::vector<std::string> values(const std::string& name) const {
    auto it = all_values_.find(name);
    return it == all_values_.end() ? std::vector<std::string>{} : it->second;
  }
  void set_flag(const std::string& name) { flags_.insert(name); }
  void set_value(const std::string& name, std::string v) {
    all_values_[name].push_back(v);
    values_[name] = std::move(v);
    flags_.insert(name);
  }

 private:
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> all_values_;
};

// Parses arguments after the verb; --help is always accepted and reported as the flag "--help".
// The error is the usage message, without the verb.
Result<Args> parse_args(std::span<char* const> arguments, const VerbSpec& spec);

// What every verb does first: parse its arguments into `args`. On a usage error it reports the
// message (fail(), report.h), on --help it prints the help text, and returns the exit code the verb
// must return at once; otherwise nothing.
std::optional<int> parse_verb_args(std::span<char* const> arguments, const VerbSpec& spec,
                                   Args& args);
std::string help_text(const VerbSpec& spec);

// The values a numeric flag accepts; NaN and the infinities never are (nor text that overflows
// a double, such as 1e400, which reads as infinity).
struct NumberRange {
  double min = -std::numeric_limits<double>::max();
  double max = std::numeric_limits<double>::max();
  bool above_min = false;  // min itself is refused: (min, max]
};
inline constexpr NumberRange kAnyNumber{};
inline constexpr NumberRange kNonNegative{0, std::numeric_limits<double>::max()};
inline constexpr NumberRange kFraction{0, 1, true};  // (0, 1]
inline constexpr NumberRange kPercent{0, 100};
// Constraint-plane weights (SimplifyOptions::boundary_weight): 0 turns them off; far above the
// default 1 they only pin the boundary harder, and 10^6 already pins it.
inline constexpr NumberRange kBoundaryWeights{0, 1e6};
// SimplifyOptions::independent_rounds: a fraction of the vertices, 0 for off.
inline constexpr NumberRange kRoundFractions{0, 1};
// Vertex and face numbers are 32-bit, with the top value meaning "none" (kNoIndex).
inline constexpr uint64_t kMaxVertexCount = 0xfffffffeu;
inline constexpr uint64_t kMaxFaceCount = 0xfffffffeu;
// Worker threads: 0 is every core; more than this are not threads but a typo.
inline constexpr uint64_t kMaxThreads = 1024;
// Hausdorff area samples: 10^10 is hours of work; a larger count is a typo.
inline constexpr uint64_t kMaxSamples = 10'000'000'000;

// Every numeric flag is read here: a number in `range`, or an error that names the flag, the
// range and what was given ("--ratio needs a number in (0, 1], got '2'").
Result<double> parse_number(const std::string& flag, const std::string& text,
                            NumberRange range = kAnyNumber);
// A whole number in [min, max] (digits only; "1e3" and "-1" are refused, so are values past
// max, which a double could not even hold exactly).
Result<uint64_t> parse_whole(const std::string& flag, const std::string& text, uint64_t min,
                             uint64_t max);
// What a flag's value looks like in messages: quoted, and cut to a few dozen characters.
std::string quoted_value(const std::string& text);

}  // namespace dynpm::cli

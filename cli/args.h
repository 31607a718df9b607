// Command-line flags for one verb: "--name value", "--name=value", "-o value", boolean
// "--flag", and positional arguments; "--" ends the flags. Unknown flags are errors.
#pragma once

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
  std::optional<std::string> value(const std::string& name) const;
  void set_flag(const std::string& name) { flags_.insert(name); }
  void set_value(const std::string& name, std::string v) {
    values_[name] = std::move(v);
    flags_.insert(name);
  }

 private:
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
};

// Parses arguments after the verb; --help is always accepted and reported as the flag "--help".
Result<Args> parse_args(std::span<char* const> arguments, const VerbSpec& spec);

// What every verb does first: parse its arguments into `args`. On a usage error it prints the
// message, on --help the help text, and returns the exit code the verb must return at once;
// otherwise nothing.
std::optional<int> parse_verb_args(std::span<char* const> arguments, const VerbSpec& spec,
                                   Args& args);
std::string help_text(const VerbSpec& spec);

// A flag's value as a number; the error names the flag ("--ratio needs a number, got 'x'").
Result<double> parse_number(const std::string& flag, const std::string& text);

}  // namespace dynpm::cli

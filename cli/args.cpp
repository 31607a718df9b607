#include "args.h"

#include <iostream>

namespace dynpm::cli {

std::optional<std::string> Args::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

Result<Args> parse_args(std::span<char* const> arguments, const VerbSpec& spec) {
  Args args;
  bool flags_ended = false;
  for (size_t i = 0; i < arguments.size(); ++i) {
    std::string arg = arguments[i];
    if (flags_ended || arg.size() < 2 || arg[0] != '-') {
      args.positional.push_back(arg);
      continue;
    }
    if (arg == "--") {
      flags_ended = true;
      continue;
    }
    if (arg == "--help" || arg == "-h") {
      args.set_flag("--help");
      continue;
    }
    std::optional<std::string> inline_value;
    if (const size_t eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      inline_value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    const FlagSpec* flag = nullptr;
    for (const FlagSpec& f : spec.flags)
      if (f.name == arg || (!f.short_name.empty() && f.short_name == arg)) flag = &f;
    if (!flag)
      return Status::error("dynpm " + spec.name + ": unknown option '" + arg + "' (see dynpm " +
                           spec.name + " --help)");
    if (!flag->takes_value) {
      if (inline_value)
        return Status::error("dynpm " + spec.name + ": " + flag->name + " takes no value");
      args.set_flag(flag->name);
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= arguments.size())
        return Status::error("dynpm " + spec.name + ": " + flag->name + " needs a value (" +
                             flag->value_name + ")");
      inline_value = arguments[++i];
    }
    args.set_value(flag->name, *inline_value);
  }
  return args;
}

std::optional<int> parse_verb_args(std::span<char* const> arguments, const VerbSpec& spec,
                                   Args& args) {
  auto parsed = parse_args(arguments, spec);
  if (!parsed) {
    std::cerr << parsed.message() << "\n";
    return 2;  // bad usage
  }
  if (parsed->has("--help")) {
    std::cout << help_text(spec);
    return 0;
  }
  args = std::move(parsed).value();
  return std::nullopt;
}

std::string help_text(const VerbSpec& spec) {
  std::string text = "usage: " + spec.usage + "\n\n" + spec.description + "\n";
  if (!spec.flags.empty()) text += "\noptions:\n";
  for (const FlagSpec& f : spec.flags) {
    std::string left = "  " + (f.short_name.empty() ? "" : f.short_name + ", ") + f.name;
    if (f.takes_value) left += " " + f.value_name;
    if (left.size() < 28)
      left.resize(28, ' ');
    else
      left += "\n" + std::string(28, ' ');
    text += left + f.help + "\n";
  }
  text += "  -h, --help                show this help\n";
  return text;
}

Result<double> parse_number(const std::string& flag, const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (...) {
  }
  return Status::error(flag + " needs a number, got '" + text + "'");
}

}  // namespace dynpm::cli

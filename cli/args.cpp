#include "args.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "dynpm/text.h"
#include "progress.h"
#include "report.h"

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
      return Status::error("unknown option " + quoted_value(arg) + " (see dynpm " + spec.name +
                           " --help)");
    if (!flag->takes_value) {
      if (inline_value) return Status::error(flag->name + " takes no value");
      args.set_flag(flag->name);
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= arguments.size())
        return Status::error(flag->name + " needs a value (" + flag->value_name + ")");
      inline_value = arguments[++i];
    }
    args.set_value(flag->name, *inline_value);
  }
  return args;
}

std::optional<int> parse_verb_args(std::span<char* const> arguments, const VerbSpec& spec,
                                   Args& args) {
  auto parsed = parse_args(arguments, spec);
  if (!parsed) return fail(spec.name, kExitUsage, parsed.message());
  if (parsed->has("--help")) {
    std::cout << help_text(spec);
    return kExitOk;
  }
  args = std::move(parsed).value();
  // A verb with --progress reads it (and --quiet) here, once for all verbs.
  const bool has_progress = std::any_of(spec.flags.begin(), spec.flags.end(),
                                        [](const FlagSpec& f) { return f.name == "--progress"; });
  if (has_progress)
    if (Status s = configure_progress(args, spec.name); !s.ok())
      return fail(spec.name, kExitUsage, s.message());
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

std::string quoted_value(const std::string& text) {
  constexpr size_t kShown = 40;
  if (text.size() <= kShown) return quoted_bytes(text);
  // Appended for the reason of quoted_bytes() (GCC 12's false -Wrestrict at -O3).
  std::string quoted(1, '\'');
  quoted += printable(text.substr(0, kShown));
  quoted += "…' (" + std::to_string(text.size()) + " characters)";
  return quoted;
}

namespace {

std::string describe(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", x);
  return text;
}

std::string describe(const NumberRange& range) {
  const bool lowest = range.min == kAnyNumber.min, highest = range.max == kAnyNumber.max;
  if (lowest && highest) return "a finite number";
  if (highest)
    return std::string("a number ") + (range.above_min ? "> " : "≥ ") + describe(range.min);
  if (lowest) return "a number ≤ " + describe(range.max);
  return std::string("a number in ") + (range.above_min ? "(" : "[") + describe(range.min) + ", " +
         describe(range.max) + "]";
}

}  // namespace

Result<double> parse_number(const std::string& flag, const std::string& text, NumberRange range) {
  // The text readers' rule (dynpm/text.h): the whole text is the number; 1e400 reads as
  // infinity, refused below with NaN.
  double v = 0;
  if (parse_real(text, v) != NumberError::kNone) v = std::numeric_limits<double>::quiet_NaN();
  const bool inside =
      std::isfinite(v) && v <= range.max && (range.above_min ? v > range.min : v >= range.min);
  if (inside) return v;
  return Status::error(flag + " needs " + describe(range) + ", got " + quoted_value(text));
}

Result<uint64_t> parse_whole(const std::string& flag, const std::string& text, uint64_t min,
                             uint64_t max) {
  uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, v);
  if (!text.empty() && error == std::errc{} && stop == end && v >= min && v <= max) return v;
  return Status::error(flag + " needs a whole number in [" + std::to_string(min) + ", " +
                       std::to_string(max) + "], got " + quoted_value(text));
}

}  // namespace dynpm::cli

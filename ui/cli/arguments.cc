#include "ui/cli/arguments.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "core/util/check.h"

namespace sylva {
namespace {

const FlagSpec* FindFlag(const CommandSpec& spec, const std::string& name) {
  for (const FlagSpec& flag : spec.flags) {
    if (flag.name == name) return &flag;
  }
  return nullptr;
}

// Handles "--name=value" or "--name value"; returns the index of the last
// argument consumed.
int ParseFlag(const CommandSpec& spec, int argc, const char* const* argv, int i,
              ParsedArguments* parsed) {
  std::string text = argv[i] + 2;
  std::string value;
  const size_t equals = text.find('=');
  const bool inline_value = equals != std::string::npos;
  if (inline_value) {
    value = text.substr(equals + 1);
    text = text.substr(0, equals);
  }
  if (spec.takes_pipeline_options && text.find('.') != std::string::npos) {
    if (!inline_value) {
      SYLVA_CHECK_INPUT(i + 1 < argc, "--" + text) << "needs a value";
      value = argv[++i];
    }
    parsed->options.emplace_back(text, value);
    return i;
  }
  const FlagSpec* flag = FindFlag(spec, text);
  SYLVA_CHECK_INPUT(flag != nullptr, "--" + text)
      << "unknown flag for 'sylva " << spec.name << "' (see 'sylva " << spec.name << " -h')";
  if (flag->value_name.empty()) {
    SYLVA_CHECK_INPUT(!inline_value, "--" + text) << "takes no value";
    parsed->flags[text] = "true";
    return i;
  }
  if (!inline_value) {
    SYLVA_CHECK_INPUT(i + 1 < argc, "--" + text) << "needs a value (" << flag->value_name << ")";
    value = argv[++i];
  }
  parsed->flags[text] = value;
  return i;
}

}  // namespace

std::string ParsedArguments::Get(const std::string& name, const std::string& fallback) const {
  const auto it = flags.find(name);
  return it == flags.end() ? fallback : it->second;
}

int ParsedArguments::GetInt(const std::string& name, int fallback, int min, int max) const {
  if (!Has(name)) return fallback;
  const std::string text = Get(name);
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  SYLVA_CHECK_INPUT(error == std::errc() && end == text.data() + text.size() && !text.empty(),
                    "--" + name)
      << "expected an integer, got '" << text << "'";
  SYLVA_CHECK_INPUT(value >= min && value <= max, "--" + name)
      << "must be between " << min << " and " << max << ", got " << value;
  return value;
}

double ParsedArguments::GetDouble(const std::string& name, double fallback) const {
  if (!Has(name)) return fallback;
  const std::string text = Get(name);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  SYLVA_CHECK_INPUT(error == std::errc() && end == text.data() + text.size() && !text.empty() &&
                        std::isfinite(value),
                    "--" + name)
      << "expected a number, got '" << text << "'";
  return value;
}

ParsedArguments ParseArguments(const CommandSpec& spec, int argc, const char* const* argv,
                               int first) {
  ParsedArguments parsed;
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      parsed.help = true;
    } else if (arg.rfind("--", 0) == 0 && arg.size() > 2) {
      i = ParseFlag(spec, argc, argv, i, &parsed);
    } else {
      SYLVA_CHECK_INPUT(arg.empty() || arg[0] != '-' || arg == "-", arg)
          << "unknown flag for 'sylva " << spec.name << "' (see 'sylva " << spec.name << " -h')";
      parsed.positional.push_back(arg);
    }
  }
  if (parsed.help) return parsed;
  const int count = static_cast<int>(parsed.positional.size());
  SYLVA_CHECK_INPUT(count >= spec.min_positional, "sylva " + spec.name)
      << "missing arguments; usage: " << spec.usage;
  SYLVA_CHECK_INPUT(count <= spec.max_positional, parsed.positional.back())
      << "unexpected argument; usage: " << spec.usage;
  return parsed;
}

std::string CommandHelp(const CommandSpec& spec) {
  std::ostringstream out;
  out << "usage: " << spec.usage << "\n\n" << spec.description << "\n";
  if (!spec.flags.empty()) out << "\nflags:\n";
  for (const FlagSpec& flag : spec.flags) {
    std::string left = "  --" + flag.name + (flag.value_name.empty() ? "" : " " + flag.value_name);
    if (left.size() < 26) left.resize(26, ' ');
    out << left << " " << flag.help << "\n";
  }
  out << "  -h, --help               show this help\n";
  return out.str();
}

}  // namespace sylva

// Command-line parsing for the sylva binary: each command declares its flags;
// --Section.field=value options go to the option registry.
#ifndef SYLVA_UI_CLI_ARGUMENTS_H_
#define SYLVA_UI_CLI_ARGUMENTS_H_

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace sylva {

struct FlagSpec {
  std::string name;        // without dashes: "photos"
  std::string value_name;  // "DIR"; empty for switches such as --force
  std::string help;
};

struct CommandSpec {
  std::string name;
  std::string usage;        // "sylva init PROJECT --photos DIR ..."
  std::string description;  // a paragraph
  std::vector<FlagSpec> flags;
  int min_positional = 0;
  int max_positional = 0;
  bool takes_pipeline_options = false;  // accepts --Section.field=value
};

struct ParsedArguments {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;                  // switches map to "true"
  std::vector<std::pair<std::string, std::string>> options;  // Section.field, value
  bool help = false;

  bool Has(const std::string& name) const { return flags.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  // Throws InputError("--name", ...) if not an integer in [min, max].
  int GetInt(const std::string& name, int fallback, int min, int max) const;
  double GetDouble(const std::string& name, double fallback) const;
};

// Parses argv[first..]; throws InputError naming the offending argument.
ParsedArguments ParseArguments(const CommandSpec& spec, int argc, const char* const* argv,
                               int first);

// Usage, description and flags of a command.
std::string CommandHelp(const CommandSpec& spec);

}  // namespace sylva

#endif  // SYLVA_UI_CLI_ARGUMENTS_H_

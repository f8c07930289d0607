// Option names in error messages are options the user can set: every
// "Section.field" that library code names in SYLVA_CHECK_INPUT or
// SYLVA_INPUT_ERROR is a key of the option registry (the one source of the
// names), so `sylva run P --Section.field=bad` is refused with a message
// naming an option the command line accepts.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "core/util/file_util.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// Sections of option structs that no command reaches through the registry,
// and why. A name in any other section must be registered.
const std::map<std::string, std::string> kInternalSections = {
    {"SyntheticTreeOptions", "the synthetic generator (sylva synth has its own flags)"},
    {"MeshRenderOptions", "the report's silhouette renderer, set from Report.*"},
    {"TreePreview", "the report's previews, set from Report.preview_size"},
    {"GltfExport", "glTF notes written by the stages, not set by users"},
    {"CrownVolume", "set from TreeMetrics.* by the mesh stage"},
    {"Phyllotaxis", "a library struct; the pipeline checks its values as Leaves.* first"},
    {"QsmToSkeleton", "sylva mesh-qsm's --merge flag"},
    {"ScanTracing", "the scanned-drawing reader; to be registered with sylva sketch (issue 14)"},
};
// Single fields of registered sections that no command sets, and why.
const std::map<std::string, std::string> kInternalOptions = {
    {"Allometry.trunk_radius", "set by the skeleton stage from Skeleton.trunk_radius"},
    {"Allometry.min_radius", "set by the skeleton stage from Skeleton.min_radius_fraction"},
    {"BranchMesh.bark", "the bark's material (name and colour), set in code"},
    {"Twigs.material", "the twigs' material (name and colour), set in code"},
};

// The option name a SYLVA_CHECK_INPUT / SYLVA_INPUT_ERROR call at `open`
// (the index of its '(') gives as its source, or "" if its source is not a
// literal "Section.field". The source is the macro's last argument.
std::string NamedOption(const std::string& text, size_t open) {
  int depth = 0;
  std::string last_literal;
  bool literal_is_last = false;
  for (size_t i = open; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      size_t end = i + 1;  // the closing quote, past escaped ones
      while (end < text.size() && text[end] != '"') end += text[end] == '\\' ? 2 : 1;
      if (end >= text.size()) return "";
      last_literal = text.substr(i + 1, end - i - 1);
      literal_is_last = true;
      i = end;
      continue;
    }
    if (c == '\'') {  // a character literal, e.g. ','
      i = text.find('\'', i + 1 + (text[i + 1] == '\\'));
      if (i == std::string::npos) return "";
      continue;
    }
    if (c == '(') ++depth;
    if (c == ')' && --depth == 0) break;
    if (c == ',' && depth == 1) literal_is_last = false;
    if (!std::isspace(static_cast<unsigned char>(c)) && c != '(' && c != ',' && c != ')') {
      literal_is_last = false;
    }
  }
  if (!literal_is_last) return "";
  const size_t dot = last_literal.find('.');
  if (dot == std::string::npos || dot == 0 || !std::isupper(last_literal[0])) return "";
  for (size_t i = dot + 1; i < last_literal.size(); ++i) {
    const char c = last_literal[i];
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(c) || c == '_')) return "";
  }
  return dot + 1 < last_literal.size() ? last_literal : "";
}

// Every option named in the library's sources, with a file that names it.
std::map<std::string, std::string> NamedOptions() {
  std::map<std::string, std::string> names;
  for (const char* folder : {"core", "reconstruct", "simulate", "mesh", "sketch", "ui"}) {
    for (const auto& entry :
         fs::recursive_directory_iterator(fs::path(SYLVA_SOURCE_DIR) / folder)) {
      const std::string extension = entry.path().extension().string();
      const std::string stem = entry.path().stem().string();
      const bool test = stem.size() > 5 && stem.compare(stem.size() - 5, 5, "_test") == 0;
      if ((extension != ".cc" && extension != ".h") || test) {
        continue;
      }
      const std::string text = ReadFileToString(entry.path());
      for (const std::string macro : {"SYLVA_CHECK_INPUT(", "SYLVA_INPUT_ERROR("}) {
        for (size_t at = text.find(macro); at != std::string::npos; at = text.find(macro, at + 1)) {
          if (at > 0 && text[at - 1] == ' ' && text.compare(at - 8, 8, "#define ") == 0) continue;
          const std::string name = NamedOption(text, at + macro.size() - 1);
          if (!name.empty()) names.emplace(name, entry.path().string());
        }
      }
    }
  }
  return names;
}

TEST(OptionNamesTest, TheScannerReadsMacroCalls) {
  const std::string text =
      "SYLVA_CHECK_INPUT(a >= 0 && f(b, c), \"Density.resolution\") << \"x\";\n"
      "SYLVA_CHECK_INPUT(ok, path.string()) << \"y\";\n"
      "SYLVA_INPUT_ERROR(\"Twigs.segments\") << \"z\";\n"
      "SYLVA_CHECK_INPUT(c == ',', \"not an option\");\n";
  EXPECT_EQ(NamedOption(text, text.find('(')), "Density.resolution");
  const size_t second = text.find("SYLVA_CHECK_INPUT(ok");
  EXPECT_EQ(NamedOption(text, text.find('(', second)), "");
  EXPECT_EQ(NamedOption(text, text.find('(', text.find("SYLVA_INPUT_ERROR"))), "Twigs.segments");
  EXPECT_EQ(NamedOption(text, text.find('(', text.find("c == ','"))), "");
}

TEST(OptionNamesTest, EveryCheckedOptionIsRegistered) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  const std::map<std::string, std::string> named = NamedOptions();
  ASSERT_GT(named.size(), 100u);  // the scanner finds the checks
  std::set<std::string> sections;
  for (const auto& entry : registry.entries()) {
    sections.insert(entry.key.substr(0, entry.key.find('.')));
  }
  for (const auto& [name, file] : named) {
    const std::string section = name.substr(0, name.find('.'));
    if (kInternalSections.count(section) != 0) {
      EXPECT_EQ(sections.count(section), 0u) << section << " is registered after all";
      continue;
    }
    if (kInternalOptions.count(name) != 0) {
      EXPECT_FALSE(registry.Has(name)) << name << " is registered after all";
      continue;
    }
    EXPECT_TRUE(registry.Has(name))
        << file << " names " << name << ", which the command line does not accept";
  }
}

// Every registered option is accepted back on the command line with its
// default value, and the registry's text round-trips.
TEST(OptionNamesTest, EveryRegisteredOptionIsAcceptedWithItsDefault) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  for (const auto& entry : registry.entries()) {
    const std::string text = registry.Get(entry.key);
    EXPECT_NO_THROW(registry.Set(entry.key, text, "--" + entry.key)) << entry.key << "=" << text;
    EXPECT_EQ(registry.Get(entry.key), text) << entry.key;
  }
  EXPECT_NO_THROW(options.Check());
}

}  // namespace
}  // namespace sylva

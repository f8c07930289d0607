#include "ui/pipeline/option_registry.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/util/check.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {
namespace {

TEST(OptionRegistryTest, SetGetAndJsonRoundTrip) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  registry.Set("Density.resolution", "64", "--Density.resolution");
  registry.Set("Density.tolerance", "0.0001", "test");
  registry.Set("Report.write_images", "false", "test");
  registry.Set("Density.bounds", "-1,-1,0,1,1,2.5", "test");
  registry.Set("General.seed", "18446744073709551615", "test");
  EXPECT_EQ(options.density.resolution, 64);
  EXPECT_DOUBLE_EQ(options.density.tolerance, 1e-4);
  EXPECT_FALSE(options.report.write_images);
  EXPECT_DOUBLE_EQ(options.density.bounds.max().z(), 2.5);
  EXPECT_EQ(options.general.seed, 18446744073709551615ULL);
  EXPECT_DOUBLE_EQ(std::stod(registry.Get("Density.tolerance")), 1e-4);

  const nlohmann::json changed = registry.ToJson(/*only_changed=*/true);
  EXPECT_EQ(changed["Density"]["resolution"], 64);
  EXPECT_FALSE(changed["Density"].contains("max_iterations"));

  PipelineOptions other;
  OptionRegistry other_registry;
  RegisterPipelineOptions(&other, &other_registry);
  other_registry.SetFromJson(changed, "sylva.json");
  EXPECT_EQ(other_registry.ToJson(false), registry.ToJson(false));
}

TEST(OptionRegistryTest, BadValuesNameTheSourceAndKey) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  const auto expect_error = [&](const std::string& key, const std::string& value,
                                const std::string& fragment) {
    try {
      registry.Set(key, value, "--" + key);
      FAIL() << key << "=" << value << " accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), "--" + key);
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  expect_error("Density.resolution", "abc", "expected an integer");
  expect_error("Density.resolution", "12.5", "expected an integer");
  expect_error("Density.tolerance", "1e", "expected a number");
  expect_error("Density.tolerance", "nan", "expected a number");
  expect_error("Report.write_images", "maybe", "expected true or false");
  expect_error("Density.bounds", "1,2,3", "six numbers");
  expect_error("Density.nosuch", "1", "unknown option");
  // Values that parse but violate a constraint are caught by Check().
  registry.Set("Density.resolution", "-3", "cli");
  try {
    options.Check();
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Density.resolution");
  }
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"Report.preview_size", "32"}, {"Report.preview_samples_per_axis", "0"}}) {
    PipelineOptions preview_options;
    OptionRegistry preview_registry;
    RegisterPipelineOptions(&preview_options, &preview_registry);
    preview_registry.Set(key, value, "cli");
    try {
      preview_options.Check();
      FAIL() << key << "=" << value << " accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), key);
    }
  }
}

TEST(OptionRegistryTest, HelpListsEveryOptionWithDefaultAndUnit) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  const std::string help = registry.Help();
  for (const auto& entry : registry.entries()) {
    EXPECT_NE(help.find("--" + entry.key + "="), std::string::npos) << entry.key;
  }
  EXPECT_NE(help.find("--Density.resolution=<int>  (default 128, voxels)"), std::string::npos)
      << help;
  EXPECT_EQ(registry.Help({"Report"}).find("Density."), std::string::npos);
}

}  // namespace
}  // namespace sylva

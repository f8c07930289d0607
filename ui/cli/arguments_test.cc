#include "ui/cli/arguments.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

CommandSpec Spec() {
  return {"init", "sylva init P", "test", {{"photos", "DIR", ""}, {"copy", "", ""}}, 1, 1, true};
}

ParsedArguments Parse(std::vector<const char*> argv) {
  argv.insert(argv.begin(), {"sylva", "init"});
  return ParseArguments(Spec(), static_cast<int>(argv.size()), argv.data(), 2);
}

TEST(ArgumentsTest, FlagsSwitchesPositionalAndOptions) {
  const ParsedArguments a = Parse({"proj", "--photos", "dir one", "--copy",
                                   "--Density.resolution=64", "--Report.write_images", "false"});
  EXPECT_EQ(a.positional, std::vector<std::string>{"proj"});
  EXPECT_EQ(a.Get("photos"), "dir one");
  EXPECT_TRUE(a.Has("copy"));
  ASSERT_EQ(a.options.size(), 2u);
  EXPECT_EQ(a.options[0].first, "Density.resolution");
  EXPECT_EQ(a.options[1].second, "false");
  EXPECT_EQ(Parse({"proj", "--photos=x"}).Get("photos"), "x");
  EXPECT_TRUE(Parse({"-h"}).help);
}

TEST(ArgumentsTest, ErrorsNameTheArgument) {
  const auto error_source = [](std::vector<const char*> argv) {
    try {
      Parse(argv);
    } catch (const InputError& error) {
      return error.source();
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_source({"proj", "--nope"}), "--nope");
  EXPECT_EQ(error_source({"proj", "--photos"}), "--photos");
  EXPECT_EQ(error_source({"proj", "--copy=yes"}), "--copy");
  EXPECT_EQ(error_source({"proj", "extra"}), "extra");
  EXPECT_EQ(error_source({}), "sylva init");
  EXPECT_EQ(error_source({"proj", "-x"}), "-x");
}

TEST(ArgumentsTest, NumericFlagsAreValidated) {
  const ParsedArguments a = Parse({"proj", "--photos", "12"});
  EXPECT_EQ(a.GetInt("photos", 0, 0, 100), 12);
  EXPECT_THROW(a.GetInt("photos", 0, 20, 100), InputError);
  EXPECT_EQ(a.GetInt("missing", 7, 0, 100), 7);
  EXPECT_THROW(Parse({"proj", "--photos", "1x"}).GetInt("photos", 0, 0, 100), InputError);
}

}  // namespace
}  // namespace sylva

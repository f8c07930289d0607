#include "core/util/check.h"

#include <gtest/gtest.h>

#include "core/util/progress.h"

namespace sylva {
namespace {

TEST(CheckTest, PassingChecksDoNotThrow) {
  EXPECT_NO_THROW(SYLVA_CHECK(1 + 1 == 2) << "never");
  EXPECT_NO_THROW(SYLVA_CHECK_INPUT(true, "file") << "never");
}

TEST(CheckTest, InternalCheckCarriesLocationAndMessage) {
  try {
    SYLVA_CHECK(2 < 1) << "value " << 42;
    FAIL() << "did not throw";
  } catch (const InputError&) {
    FAIL() << "wrong type";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("check_test.cc"), std::string::npos) << message;
    EXPECT_NE(message.find("2 < 1"), std::string::npos) << message;
    EXPECT_NE(message.find("value 42"), std::string::npos) << message;
  }
}

TEST(CheckTest, InputErrorNamesTheSource) {
  try {
    SYLVA_CHECK_INPUT(false, "photos/a.png") << "image is empty";
    FAIL() << "did not throw";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "photos/a.png: image is empty");
    EXPECT_EQ(error.source(), "photos/a.png");
    EXPECT_EQ(error.message(), "image is empty");
  }
}

class RecordingReporter : public ProgressReporter {
 public:
  void Update(std::string_view task, double fraction) override {
    last_task = std::string(task);
    last_fraction = fraction;
  }
  std::string last_task;
  double last_fraction = -1;
};

TEST(ProgressTest, SubTasksMapIntoParentRangeAndCancel) {
  RecordingReporter reporter;
  ProgressTask task(&reporter, "all", 0.0, 1.0);
  ProgressTask second_half = task.SubTask("half", 0.5, 1.0);
  second_half.Update(1.0);
  EXPECT_EQ(reporter.last_task, "half");
  EXPECT_DOUBLE_EQ(reporter.last_fraction, 1.0);
  ProgressTask quarter = second_half.SubTask("q", 0.0, 0.5);
  quarter.Update(1.0);
  EXPECT_DOUBLE_EQ(reporter.last_fraction, 0.75);
  reporter.RequestCancel();
  EXPECT_THROW(quarter.Update(0.5), Cancelled);
  EXPECT_THROW(quarter.CheckCancelled(), Cancelled);
  ProgressTask silent(nullptr, "none");
  EXPECT_NO_THROW(silent.Update(0.5));
}

}  // namespace
}  // namespace sylva

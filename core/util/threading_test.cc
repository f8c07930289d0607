#include "core/util/threading.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>

namespace sylva {
namespace {

TEST(ThreadingTest, RunsEveryIndexAndRethrowsTheFirstError) {
  std::atomic<int> sum{0};
  ParallelForFirstError(100, [&](int i) { sum += i; });
  EXPECT_EQ(sum.load(), 4950);
  for (int attempt = 0; attempt < 20; ++attempt) {
    try {
      ParallelForFirstError(64, [](int i) {
        if (i % 7 == 3) throw std::runtime_error(std::to_string(i));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()), "3");
    }
  }
  EXPECT_NO_THROW(ParallelForFirstError(0, [](int) { throw 1; }));
}

}  // namespace
}  // namespace sylva

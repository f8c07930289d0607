#include "reconstruct/matting/matting.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(MattingOptionsTest, DefaultsPass) { MattingOptions().Check(); }

}  // namespace
}  // namespace sylva

#include "reconstruct/density/density_edits.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(DensityEditTest, MixesThePaintedOpacityByAlpha) {
  FloatImage matte(3, 1, 1, 0.5f);
  FloatImage edit(3, 1, 4, 0.0f);
  // Pixel 0 untouched; pixel 1 painted in fully; pixel 2 erased half-way.
  for (int c = 0; c < 3; ++c) edit.at(1, 0, c) = 1.0f;
  edit.at(1, 0, 3) = 1.0f;
  edit.at(2, 0, 3) = 0.5f;
  ApplyDensityEdit(edit, "edit.png", &matte);
  EXPECT_FLOAT_EQ(matte.at(0, 0), 0.5f);
  EXPECT_FLOAT_EQ(matte.at(1, 0), 1.0f);
  EXPECT_FLOAT_EQ(matte.at(2, 0), 0.25f);
}

TEST(DensityEditTest, GreyAndAlphaWorkToo) {
  FloatImage matte(1, 1, 1, 1.0f);
  FloatImage edit(1, 1, 2, 0.0f);
  edit.at(0, 0, 1) = 1.0f;  // erase
  ApplyDensityEdit(edit, "edit.png", &matte);
  EXPECT_FLOAT_EQ(matte.at(0, 0), 0.0f);
}

TEST(DensityEditTest, AnEditWithoutAlphaOrOfAnotherSizeIsNamed) {
  FloatImage matte(4, 4, 1, 0.0f);
  try {
    ApplyDensityEdit(FloatImage(4, 4, 3, 1.0f), "rgb.png", &matte);
    ADD_FAILURE() << "no error for an edit without alpha";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "rgb.png");
  }
  EXPECT_THROW(ApplyDensityEdit(FloatImage(5, 4, 4, 1.0f), "small.png", &matte), InputError);
}

}  // namespace
}  // namespace sylva

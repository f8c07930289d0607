#include "reconstruct/density/density_edits.h"

#include <algorithm>

#include "core/util/check.h"

namespace sylva {

void ApplyDensityEdit(const FloatImage& edit, const std::string& source, FloatImage* matte) {
  SYLVA_CHECK(matte != nullptr && matte->channels() == 1);
  SYLVA_CHECK_INPUT(edit.channels() == 2 || edit.channels() == 4, source)
      << "a density edit needs an alpha channel (grey + alpha or RGBA), got " << edit.channels()
      << " channel(s)";
  SYLVA_CHECK_INPUT(edit.width() == matte->width() && edit.height() == matte->height(), source)
      << "a density edit must have its photo's size, " << matte->width() << " x " << matte->height()
      << ", got " << edit.width() << " x " << edit.height();
  const int alpha_channel = edit.channels() - 1;
  for (int y = 0; y < matte->height(); ++y) {
    for (int x = 0; x < matte->width(); ++x) {
      const float alpha = std::clamp(edit.at(x, y, alpha_channel), 0.0f, 1.0f);
      if (alpha <= 0.0f) continue;
      float grey = 0.0f;
      for (int c = 0; c < alpha_channel; ++c) grey += edit.at(x, y, c);
      grey = std::clamp(grey / alpha_channel, 0.0f, 1.0f);
      matte->at(x, y) = (1.0f - alpha) * matte->at(x, y) + alpha * grey;
    }
  }
}

FloatImage AddedOpacity(const FloatImage& edited, const FloatImage& computed) {
  SYLVA_CHECK(edited.width() == computed.width() && edited.height() == computed.height() &&
              edited.channels() == 1 && computed.channels() == 1);
  FloatImage added(edited.width(), edited.height(), 1);
  for (size_t i = 0; i < added.values().size(); ++i) {
    added.values()[i] = std::max(0.0f, edited.values()[i] - computed.values()[i]);
  }
  return added;
}

}  // namespace sylva

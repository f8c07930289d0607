// Zhang & Suen 1984 thinning of a binary image to a one-pixel skeleton, and
// the 8-neighbour codes it is built on. Shared by the scanned drawings'
// centre lines (sketch/scan_skeleton.h, which also traces skeletons with the
// neighbour codes) and the livewire seeds at a mask's tips
// (reconstruct/attractors). It replaces cv::ximgproc::thinning, with the
// same result: OpenCV's contrib module links GDAL, video and 140 more
// libraries that a process spent 0.1 s binding at every start.
#ifndef SYLVA_CORE_UTIL_THINNING_H_
#define SYLVA_CORE_UTIL_THINNING_H_

#include <array>
#include <cstddef>
#include <cstdint>

namespace sylva {

// The 8 neighbours clockwise from north (Zhang & Suen's P2 ... P9) as
// offsets in a row-major image of `step` bytes a row; bit k of a neighbour
// code is neighbour k.
std::array<int, 8> NeighbourOffsets(size_t step);

// The neighbour code of pixel `index` (its neighbours must lie inside).
inline int NeighbourCode(const uint8_t* data, int index, const std::array<int, 8>& offsets) {
  int code = 0;
  for (int k = 0; k < 8; ++k) code |= (data[index + offsets[k]] != 0) << k;
  return code;
}

// 0 -> 1 transitions around the neighbours: the number of branches that
// leave a pixel (1 at an end, 2 along a line, >= 3 at a junction).
int CrossingNumber(int code);

// Thins the ink (non-zero) of a row-major `width` x `height` image of
// `step` bytes a row in place to its Zhang & Suen skeleton: 255 on the
// skeleton, 0 elsewhere. The image's border pixels are never removed (as
// in OpenCV). Each sub-iteration visits only the pixels on the ink's
// current boundary, so the cost follows the ink's area, not the image's.
void ThinZhangSuen(int width, int height, size_t step, uint8_t* pixels);

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_THINNING_H_

#include "core/util/thinning.h"

#include <algorithm>
#include <vector>

namespace sylva {
namespace {

constexpr int kDx[8] = {0, 1, 1, 1, 0, -1, -1, -1};
constexpr int kDy[8] = {-1, -1, 0, 1, 1, 1, 0, -1};

bool Bit(int code, int k) { return (code >> (k & 7)) & 1; }

// Zhang & Suen's deletion test for sub-iteration `pass` (0 or 1).
bool Deletable(int code, int pass) {
  const int count = __builtin_popcount(code);
  const bool p2 = Bit(code, 0), p4 = Bit(code, 2), p6 = Bit(code, 4), p8 = Bit(code, 6);
  const bool m1 = pass == 0 ? (p2 && p4 && p6) : (p2 && p4 && p8);
  const bool m2 = pass == 0 ? (p4 && p6 && p8) : (p2 && p6 && p8);
  return CrossingNumber(code) == 1 && count >= 2 && count <= 6 && !m1 && !m2;
}

// Removes the pixels of `candidates` that sub-iteration `pass` deletes (all
// at once, as Zhang & Suen's parallel rule says); returns them.
std::vector<int> ThinningPass(const std::vector<int>& candidates, int pass,
                              const std::array<int, 8>& offsets,
                              const std::array<std::array<bool, 256>, 2>& deletable,
                              uint8_t* data) {
  std::vector<int> deleted;
  for (int index : candidates) {
    if (data[index] && deletable[pass][NeighbourCode(data, index, offsets)]) {
      deleted.push_back(index);
    }
  }
  for (int index : deleted) data[index] = 0;
  return deleted;
}

}  // namespace

std::array<int, 8> NeighbourOffsets(size_t step) {
  std::array<int, 8> offsets;
  for (int k = 0; k < 8; ++k) offsets[k] = kDy[k] * static_cast<int>(step) + kDx[k];
  return offsets;
}

int CrossingNumber(int code) {
  int transitions = 0;
  for (int k = 0; k < 8; ++k) transitions += !Bit(code, k) && Bit(code, k + 1);
  return transitions;
}

void ThinZhangSuen(int width, int height, size_t step, uint8_t* data) {
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) data[y * step + x] = data[y * step + x] != 0 ? 255 : 0;
  }
  const std::array<int, 8> offsets = NeighbourOffsets(step);
  std::array<std::array<bool, 256>, 2> deletable;
  for (int code = 0; code < 256; ++code) {
    for (int pass = 0; pass < 2; ++pass) deletable[pass][code] = Deletable(code, pass);
  }
  // Candidates: ink pixels off the image border with paper among their
  // neighbours (only those can ever be deleted); `listed` avoids repeats.
  const int row = static_cast<int>(step);
  const auto inside = [&](int index) {
    const int x = index % row, y = index / row;
    return x > 0 && y > 0 && x < width - 1 && y < height - 1;
  };
  std::vector<uint8_t> listed(step * height, 0);
  std::vector<int> candidates;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int index = y * row + x;
      if (data[index] && inside(index) && NeighbourCode(data, index, offsets) != 255) {
        candidates.push_back(index);
        listed[index] = 1;
      }
    }
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<int> deleted = ThinningPass(candidates, pass, offsets, deletable, data);
      changed |= !deleted.empty();
      // Deleting a pixel exposes its ink neighbours to the paper.
      candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                      [&](int index) { return !data[index]; }),
                       candidates.end());
      for (int index : deleted) {
        for (int offset : offsets) {
          const int n = index + offset;
          if (data[n] && !listed[n] && inside(n)) {
            listed[n] = 1;
            candidates.push_back(n);
          }
        }
      }
    }
  }
}

}  // namespace sylva

// Small statistics over plain vectors.
#ifndef SYLVA_CORE_UTIL_STATISTICS_H_
#define SYLVA_CORE_UTIL_STATISTICS_H_

#include <algorithm>
#include <vector>

namespace sylva {

// The median (the mean of the two middle values for an even count); 0 for
// no values.
inline double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  if (values.size() % 2 == 1) return values[mid];
  return 0.5 * (values[mid] + *std::max_element(values.begin(), values.begin() + mid));
}

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_STATISTICS_H_

#include "simulate/direction_field.h"

#include "core/util/check.h"

namespace sylva {

ConstantDirectionField::ConstantDirectionField(const Eigen::Vector3d& direction_in_world) {
  SYLVA_CHECK_INPUT(direction_in_world.allFinite(), "direction field")
      << "the constant direction must be finite";
  const double norm = direction_in_world.norm();
  if (norm > 0) direction_in_world_ = direction_in_world / norm;
}

}  // namespace sylva

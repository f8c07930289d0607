// The external direction hook of the particle flow (thesis 3.5): a direction
// per world point that steers particles, e.g. towards the attractor graphs
// drawn or traced on the photos. The particle flow adds
// `ParticleFlowOptions::field_weight * Direction(x)` to each particle's
// acceleration.
#ifndef SYLVA_SIMULATE_DIRECTION_FIELD_H_
#define SYLVA_SIMULATE_DIRECTION_FIELD_H_

#include <Eigen/Core>

namespace sylva {

// Thread-safe: Direction() is const and may be called concurrently, many
// times per particle and step, so it should be cheap (precompute in the
// constructor).
class DirectionField {
 public:
  virtual ~DirectionField() = default;
  // A direction (unit length, or zero for none) at a world point, in the
  // world frame.
  virtual Eigen::Vector3d Direction(const Eigen::Vector3d& point_in_world) const = 0;
};

// The same direction everywhere; zero (no steering) by default.
class ConstantDirectionField : public DirectionField {
 public:
  ConstantDirectionField() = default;
  // `direction_in_world` is normalised; zero means no steering. Throws
  // InputError if it is not finite.
  explicit ConstantDirectionField(const Eigen::Vector3d& direction_in_world);

  Eigen::Vector3d Direction(const Eigen::Vector3d& /*point_in_world*/) const override {
    return direction_in_world_;
  }

 private:
  Eigen::Vector3d direction_in_world_ = Eigen::Vector3d::Zero();
};

}  // namespace sylva

#endif  // SYLVA_SIMULATE_DIRECTION_FIELD_H_

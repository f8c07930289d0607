#include "simulate/embree_neighbor_search.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/util/check.h"

namespace sylva {
namespace {

// Embree culls float boxes against a float query sphere; the radius is padded
// by this fraction of itself plus this fraction of the largest coordinate
// magnitude (several float roundings), so that rounding never culls a point
// that is the nearest in double precision.
constexpr double kRadiusRelativePadding = 1e-5;
constexpr double kCoordinatePadding = 1e-6;

void CheckDevice(RTCDevice device, const char* step) {
  const RTCError error = rtcGetDeviceError(device);
  SYLVA_CHECK(error == RTC_ERROR_NONE)
      << "Embree error " << static_cast<int>(error) << " in " << step;
}

// What one point query carries through Embree's traversal.
struct QueryState {
  const std::vector<Eigen::Vector3d>* points;
  Eigen::Vector3d query;
  int exclude_idx;
  double padding;  // absolute radius padding, in the points' units
  double best_distance2;
  int best_idx;
};

float PaddedRadius(double distance2, double padding) {
  return static_cast<float>(std::sqrt(distance2) * (1 + kRadiusRelativePadding) + padding);
}

// Bounds of user primitive `primID`: the degenerate box at its point.
void PointBounds(const RTCBoundsFunctionArguments* args) {
  const auto& points = *static_cast<const std::vector<Eigen::Vector3d>*>(args->geometryUserPtr);
  const Eigen::Vector3d& p = points[args->primID];
  RTCBounds* box = args->bounds_o;
  box->lower_x = box->upper_x = static_cast<float>(p.x());
  box->lower_y = box->upper_y = static_cast<float>(p.y());
  box->lower_z = box->upper_z = static_cast<float>(p.z());
}

// Called for every point in a BVH leaf the query sphere touches; shrinks the
// sphere to the best distance so far. Returns true when the radius changed.
bool PointQuery(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<QueryState*>(args->userPtr);
  const int idx = static_cast<int>(args->primID);
  if (idx == state->exclude_idx) return false;
  const double d2 = ((*state->points)[idx] - state->query).squaredNorm();
  const bool better =
      d2 < state->best_distance2 || (d2 == state->best_distance2 && idx < state->best_idx);
  if (!better) return false;
  state->best_distance2 = d2;
  state->best_idx = idx;
  const float radius = PaddedRadius(d2, state->padding);
  if (radius >= args->query->radius) return false;
  args->query->radius = radius;
  return true;
}

class EmbreeNeighborSearch final : public NeighborSearch {
 public:
  EmbreeNeighborSearch() {
    device_ = rtcNewDevice(nullptr);
    SYLVA_CHECK(device_ != nullptr) << "cannot create an Embree device";
    scene_ = rtcNewScene(device_);
    // Rebuilt every step: a fast build matters more than the best tree.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_LOW);
    geometry_ = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryBuildQuality(geometry_, RTC_BUILD_QUALITY_LOW);
    rtcSetGeometryPointQueryFunction(geometry_, PointQuery);
    rtcAttachGeometry(scene_, geometry_);
    CheckDevice(device_, "creating the point scene");
  }
  ~EmbreeNeighborSearch() override {
    rtcReleaseGeometry(geometry_);
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeNeighborSearch(const EmbreeNeighborSearch&) = delete;
  EmbreeNeighborSearch& operator=(const EmbreeNeighborSearch&) = delete;

  void Build(const std::vector<Eigen::Vector3d>& points) override {
    points_ = &points;
    double largest = 0.0;
    for (const Eigen::Vector3d& p : points) largest = std::max(largest, p.cwiseAbs().maxCoeff());
    padding_ = kCoordinatePadding * largest;
    auto* user = const_cast<std::vector<Eigen::Vector3d>*>(&points);
    rtcSetGeometryUserPrimitiveCount(geometry_, static_cast<unsigned>(points.size()));
    // The bounds callback reads the points through the geometry's user data.
    rtcSetGeometryUserData(geometry_, user);
    rtcSetGeometryBoundsFunction(geometry_, PointBounds, nullptr);
    rtcCommitGeometry(geometry_);
    rtcCommitScene(scene_);
    CheckDevice(device_, "building the point BVH");
  }

  int Nearest(const Eigen::Vector3d& query, int exclude_idx, double max_distance,
              double* distance) const override {
    const double initial2 = std::isinf(max_distance) ? std::numeric_limits<double>::infinity()
                                                     : max_distance * max_distance;
    const double padding = padding_ + kCoordinatePadding * query.cwiseAbs().maxCoeff();
    QueryState state{points_, query, exclude_idx, padding, initial2, -1};
    if (!points_->empty()) {
      RTCPointQuery point_query;
      point_query.x = static_cast<float>(query.x());
      point_query.y = static_cast<float>(query.y());
      point_query.z = static_cast<float>(query.z());
      point_query.radius = std::isinf(max_distance) ? std::numeric_limits<float>::infinity()
                                                    : PaddedRadius(initial2, padding);
      point_query.time = 0.0f;
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(scene_, &point_query, &context, nullptr, &state);
    }
    if (distance != nullptr) {
      *distance = state.best_idx >= 0 ? std::sqrt(state.best_distance2) : max_distance;
    }
    return state.best_idx;
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  RTCGeometry geometry_ = nullptr;
  double padding_ = 0.0;  // kCoordinatePadding times the largest coordinate
};

}  // namespace

std::unique_ptr<NeighborSearch> MakeEmbreeNeighborSearch() {
  return std::make_unique<EmbreeNeighborSearch>();
}

}  // namespace sylva

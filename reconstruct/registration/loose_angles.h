// The rotation of a loosely placed camera from its azimuth, elevation and
// roll, templated so that Ceres can differentiate it (loose_refinement.cc)
// and the same formula builds the initial cameras (loose_registration.cc).
// Internal to reconstruct/registration.
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_ANGLES_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_ANGLES_H_

#include <cmath>

namespace sylva {

// angles = (azimuth, elevation, roll) in radians (LoosePhoto's meanings).
// Writes the rows of cam_from_world's rotation, row-major, into r[9]: the
// camera's x (right), y (down) and z (viewing direction) axes in world
// coordinates. A camera at azimuth a, elevation e sits in direction
// (cos e cos a, cos e sin a, sin e) from the tree and looks back along it.
template <typename T>
void LooseRotationFromAngles(const T* angles, T* r) {
  using std::cos;
  using std::sin;
  const T ca = cos(angles[0]), sa = sin(angles[0]);
  const T ce = cos(angles[1]), se = sin(angles[1]);
  const T cr = cos(angles[2]), sr = sin(angles[2]);
  // Roll-free axes: x0 horizontal to the right, y0 = z x x0 pointing down.
  const T x0[3] = {-sa, ca, T(0)};
  const T y0[3] = {se * ca, se * sa, -ce};
  for (int k = 0; k < 3; ++k) {
    r[k] = cr * x0[k] + sr * y0[k];
    r[3 + k] = -sr * x0[k] + cr * y0[k];
  }
  r[6] = -ce * ca;
  r[7] = -ce * sa;
  r[8] = -se;
}

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_ANGLES_H_

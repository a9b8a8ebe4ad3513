// Eq. 1 of the paper (as restated in the design brief): the cost of a mesh face in the
// minimum cut, for one orientation of the face,
//
//   phi(f) = (1 - exp(-tan^2(pi/4 * (omega_f - 1)) / sigma^2)) * a_f  +  lambda * a_f
//
// omega_f in [0, 1] is the face's photo-consistency for that orientation (common/photo/),
// a_f its area. omega = 1 costs lambda * a_f; omega = 0 costs about (1 + lambda) * a_f.
#pragma once
#include <cmath>

namespace tetmvs::cut {

// The data part (the first term divided by a_f), in [0, 1).
inline double data_term(double omega, double sigma) {
  const double t = std::tan(M_PI / 4.0 * (omega - 1.0));
  return 1.0 - std::exp(-(t * t) / (sigma * sigma));
}

// phi(f) of Eq. 1.
inline double face_cost(double omega, double area, double lambda, double sigma) {
  return data_term(omega, sigma) * area + lambda * area;
}

}  // namespace tetmvs::cut

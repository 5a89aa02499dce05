// What the Jacobian tests share: a random state with a unit quaternion, and central differences.
#pragma once

#include <cstdlib>

#include <Eigen/Core>

#include "pose_ekf/core/process_model.h"

namespace pose_ekf {

// Uniform in [-1, 1] per element, the quaternion normalised, omega scaled by omega_scale (rad/s).
inline StateVector RandomState(int n, unsigned seed, double omega_scale) {
  srand(seed);
  StateVector x = StateVector::Random(n);
  x.segment<4>(kQ) = Eigen::Vector4d::Random().normalized();
  x.segment<3>(kW) *= omega_scale;
  return x;
}

// d f / d x by central differences (step 1e-6); f maps a state to `rows` values.
template <typename Fn>
Eigen::MatrixXd NumericJacobian(const Fn& f, const StateVector& x, int rows) {
  Eigen::MatrixXd J(rows, x.size());
  const double h = 1e-6;
  for (int i = 0; i < x.size(); ++i) {
    StateVector xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return J;
}

}  // namespace pose_ekf

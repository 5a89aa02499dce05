// Shared helpers for the pose_math tests: seeded random rotations and a
// numeric Jacobian by central differences.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <random>

#include "pose_math/quaternion.h"

namespace pose_math {
namespace test {

class Random {
 public:
  explicit Random(unsigned seed = 42) : rng_(seed) {}
  double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  double Normal() { return normal_(rng_); }
  Eigen::Vector3d Vector3(double sigma = 1.0) { return sigma * Eigen::Vector3d(Normal(), Normal(), Normal()); }
  Eigen::Vector3d UnitVector() { return Vector3().normalized(); }
  // Uniform on SO(3): a normalised 4-D Gaussian, with either sign.
  Quat UnitQuat() { return Quat(Normal(), Normal(), Normal(), Normal()).normalized(); }
  // A random symmetric positive-definite matrix with eigenvalues in [lo, hi].
  Eigen::MatrixXd Spd(int n, double lo, double hi) {
    Eigen::MatrixXd G(n, n);
    for (int i = 0; i < n * n; ++i) G.data()[i] = Normal();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
    const Eigen::MatrixXd Q = qr.householderQ();
    Eigen::VectorXd ev(n);
    for (int i = 0; i < n; ++i) ev[i] = Uniform(lo, hi);
    return Q * ev.asDiagonal() * Q.transpose();
  }

 private:
  std::mt19937 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// d f / d x at x by central differences.
inline Eigen::MatrixXd NumericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                       const Eigen::VectorXd& x, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return J;
}

}  // namespace test
}  // namespace pose_math

// Perspective-3-point, Fischler & Bolles (thesis 4.2.1), with the remaining points
// choosing among the (up to four) roots.
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <limits>

#include "cone_tracker/pose/algorithms.h"

namespace cone_tracker {
namespace {

using Poly = std::array<double, 5>;  // coefficients of x^0 .. x^4

Poly Mul(const Poly& a, const Poly& b) {
  Poly r{};
  for (int i = 0; i < 5; ++i)
    for (int j = 0; i + j < 5; ++j) r[i + j] += a[i] * b[j];
  return r;
}
Poly Sub(const Poly& a, const Poly& b) {
  Poly r{};
  for (int i = 0; i < 5; ++i) r[i] = a[i] - b[i];
  return r;
}
double Eval(const Poly& p, double x) { return (((p[4] * x + p[3]) * x + p[2]) * x + p[1]) * x + p[0]; }
double EvalDerivative(const Poly& p, double x) { return ((4 * p[4] * x + 3 * p[3]) * x + 2 * p[2]) * x + p[1]; }

// Real roots of the quartic (4.14) from the companion matrix, polished by Newton.
std::vector<double> RealRoots(const Poly& p) {
  int degree = 4;
  const double scale = std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2]), std::abs(p[3]), std::abs(p[4])});
  while (degree > 0 && std::abs(p[degree]) <= 1e-14 * scale) --degree;
  std::vector<double> roots;
  if (degree == 0) return roots;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(degree, degree);
  for (int i = 0; i < degree; ++i) companion(0, i) = -p[degree - 1 - i] / p[degree];
  for (int i = 1; i < degree; ++i) companion(i, i - 1) = 1.0;
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(companion, false);
  for (int i = 0; i < degree; ++i) {
    const std::complex<double> z = eig.eigenvalues()[i];
    if (std::abs(z.imag()) > 1e-6 * std::max(1.0, std::abs(z.real()))) continue;
    double x = z.real();
    for (int k = 0; k < 5; ++k) {
      const double d = EvalDerivative(p, x);
      if (d == 0.0) break;
      x -= Eval(p, x) / d;
    }
    roots.push_back(x);
  }
  return roots;
}

// Three well-spread points: the first, the one farthest from it, and the one
// making the largest triangle with them (collinear triples have no solution).
std::array<int, 3> ChooseTriangle(const Eigen::Matrix3Xd& model) {
  int b = 1, c = 2;
  double best = -1.0;
  for (int i = 1; i < model.cols(); ++i) {
    const double d = (model.col(i) - model.col(0)).squaredNorm();
    if (d > best) best = d, b = i;
  }
  best = -1.0;
  for (int i = 1; i < model.cols(); ++i) {
    if (i == b) continue;
    const double area = (model.col(b) - model.col(0)).cross(model.col(i) - model.col(0)).squaredNorm();
    if (area > best) best = area, c = i;
  }
  return {0, b, c};
}

}  // namespace

Estimate P3pFischlerBolles(const Correspondences& c) {
  if (c.size() < 4) return Failure("p3p needs at least 4 points (3 for the quartic, more to choose the root)");
  const std::array<int, 3> idx = ChooseTriangle(c.model);
  Eigen::Vector3d w[3];
  Eigen::Matrix3d model3;
  for (int k = 0; k < 3; ++k) {
    w[k] = Eigen::Vector3d(c.normalized(0, idx[k]), c.normalized(1, idx[k]), 1.0).normalized();  // (4.10)
    model3.col(k) = c.model.col(idx[k]);
  }
  const double cab = w[0].dot(w[1]), cac = w[0].dot(w[2]), cbc = w[1].dot(w[2]);  // (4.11)
  const double dab2 = (model3.col(0) - model3.col(1)).squaredNorm();              // (4.12)
  const double dac2 = (model3.col(0) - model3.col(2)).squaredNorm();
  const double dbc2 = (model3.col(1) - model3.col(2)).squaredNorm();
  // With b = x a, c = y a (4.13), eliminating a² leaves two quadratics in y,
  //   K y² + b1 y + c1(x) = 0 (from d_ab, d_ac) and K y² + b2(x) y + c2(x) = 0
  // (from d_ab, d_bc), K = d_ab². Their resultant is the quartic in x (4.14):
  //   K (c2 − c1)² − (b2 − b1)(b1 c2 − b2 c1) = 0.
  const double K = dab2;
  const Poly b1{-2.0 * cac * K, 0, 0, 0, 0};
  const Poly b2{0, -2.0 * cbc * K, 0, 0, 0};
  const Poly c1{K - dac2, 2.0 * cab * dac2, -dac2, 0, 0};
  const Poly c2{-dbc2, 2.0 * cab * dbc2, K - dbc2, 0, 0};
  const Poly dc = Sub(c2, c1), db = Sub(b2, b1);
  const Poly quartic = Sub(Mul(Poly{K, 0, 0, 0, 0}, Mul(dc, dc)), Mul(db, Sub(Mul(b1, c2), Mul(b2, c1))));

  Estimate best = Failure("p3p: no real positive root gives a triangle in front of the camera");
  double best_cost = std::numeric_limits<double>::infinity();
  for (const double x : RealRoots(quartic)) {
    if (x <= 0.0) continue;
    const double denom = b1[0] - (b2[1] * x);
    double y;
    if (std::abs(denom) > 1e-12 * K) {
      y = (Eval(c2, x) - Eval(c1, x)) / denom;  // subtract the two quadratics
    } else {
      const double disc = b1[0] * b1[0] - 4.0 * K * Eval(c1, x);
      if (disc < 0.0) continue;
      y = (-b1[0] + std::sqrt(disc)) / (2.0 * K);
    }
    if (y <= 0.0) continue;
    const double denom_a = 1.0 + x * x - 2.0 * x * cab;
    if (denom_a <= 0.0) continue;
    const double a = std::sqrt(dab2 / denom_a);  // (4.13)
    Eigen::Matrix3d camera3;
    camera3.col(0) = a * w[0];  // (4.15)
    camera3.col(1) = x * a * w[1];
    camera3.col(2) = y * a * w[2];
    // Absolute orientation in place of the congruent-triangle alignment (4.16) (4.17).
    const pose_math::Pose T = AbsoluteOrientationSvd(model3, camera3);
    if (MinDepth(c.model, T) <= 0.0) continue;
    const double cost = ImageSpaceCost(c, T);
    if (cost < best_cost) {
      best_cost = cost;
      best.ok = true;
      best.error.clear();
      best.T_camera_model = T;
      best.converged = true;
    }
  }
  return best;
}

}  // namespace cone_tracker

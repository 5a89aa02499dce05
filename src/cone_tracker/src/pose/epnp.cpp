// EPnP (Moreno-Noguer, Lepetit, Fua 2007, the thesis's [27]), for comparison:
// four control points on the model's scaled principal axes, the image-space
// measurement matrix, and betas from the six control-point distances —
// linearised for 1–3 eigenvectors, then Gauss–Newton on four.
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "null_space.h"

namespace cone_tracker {
namespace {

struct EpnpSetup {
  Vertices control;
  std::vector<PointMap> maps;
  Matrix12d V;
};

bool Setup(const Correspondences& c, EpnpSetup* s) {
  const Eigen::Vector3d centroid = c.model.rowwise().mean();
  // The centred model's principal axes and singular values: eigenvectors and square roots of the eigenvalues of
  // its 3x3 scatter, largest first. (The same as JacobiSVD<Matrix3Xd>'s U and singular values, at less than half
  // the compile time: .ci/README.md.)
  const Eigen::Matrix3Xd centred = c.model.colwise() - centroid;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(centred * centred.transpose());
  const double n = c.size();
  s->control.col(0) = centroid;
  for (int k = 0; k < 3; ++k) {
    const double singular = std::sqrt(std::max(eig.eigenvalues()(2 - k), 0.0));
    s->control.col(k + 1) = centroid + singular / std::sqrt(n) * eig.eigenvectors().col(2 - k);
  }
  Eigen::Matrix4Xd alpha;
  if (!Barycentric(s->control, c.model, &alpha)) return false;
  s->maps = SimplexPointMaps(alpha);
  s->V = DecomposeMeasurementMatrix(MeasurementMatrix(c, s->maps, ErrorSpace::kImage)).V;
  return true;
}

// The linearisations of the EPnP paper: unknown products β_aβ_b solved by
// least squares from the six distances, then square roots.
std::vector<Eigen::Vector4d> LinearBetas(const EpnpSetup& s) {
  std::vector<Eigen::Vector4d> out;
  for (int count = 1; count <= 3; ++count) {
    const std::vector<QuadraticConstraint> d = DistanceConstraints(s.V, count, s.control);
    const int unknowns = count * (count + 1) / 2;
    Eigen::MatrixXd L(6, unknowns);
    Eigen::VectorXd rho(6);
    for (int l = 0; l < 6; ++l) {
      int col = 0;
      for (int a = 0; a < count; ++a)
        for (int b = a; b < count; ++b) L(l, col++) = (a == b ? 1.0 : 2.0) * d[l].Q(a, b);
      rho(l) = d[l].target;
    }
    const Eigen::VectorXd bb = L.colPivHouseholderQr().solve(rho);  // products β_aβ_b, a ≤ b (4.127) (4.128)
    Eigen::Vector4d beta = Eigen::Vector4d::Zero();
    const double b11 = std::abs(bb(0));
    beta(0) = std::sqrt(b11);
    // β_b = β_aβ_b / β_a keeps the relative signs.
    if (count >= 2 && beta(0) > 0.0) beta(1) = bb(1) / beta(0);
    if (count >= 3 && beta(0) > 0.0) beta(2) = bb(2) / beta(0);
    if (beta.allFinite()) out.push_back(beta);
  }
  return out;
}

Estimate BestOf(const Correspondences& c, const EpnpSetup& s, const std::vector<Eigen::Vector4d>& candidates,
                int count_for_all) {
  Estimate best = Failure("epnp: no valid eigenvector combination");
  double best_cost = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < candidates.size(); ++k) {
    const int count = count_for_all > 0 ? count_for_all : static_cast<int>(k) + 1;
    const Estimate e = PoseFromBetas(c, s.maps, s.V, candidates[k], count);
    if (!e.ok) continue;
    const double cost = ImageSpaceCost(c, e.T_camera_model);
    if (cost < best_cost) best_cost = cost, best = e;
  }
  return best;
}

}  // namespace

Estimate EpnpLinear(const Correspondences& c) {
  if (c.size() < 6) return Failure("epnp needs at least 6 points");
  EpnpSetup s;
  if (!Setup(c, &s)) return Failure("epnp: degenerate control points");
  return BestOf(c, s, LinearBetas(s), 0);
}

Estimate EpnpGaussNewton(const Correspondences& c) {
  if (c.size() < 6) return Failure("epnp needs at least 6 points");
  EpnpSetup s;
  if (!Setup(c, &s)) return Failure("epnp: degenerate control points");
  const std::vector<QuadraticConstraint> d = DistanceConstraints(s.V, 4, s.control);
  std::vector<Eigen::Vector4d> refined;
  for (const Eigen::Vector4d& beta0 : LinearBetas(s)) refined.push_back(GaussNewtonBetas(d, 4, beta0, 10));
  Estimate e = BestOf(c, s, refined, 4);
  e.iterations = 10;
  return e;
}

}  // namespace cone_tracker

// Eigenvector combinations with shape constraints on the betas, shared by
// EPnP and the 3-simplex SDP (thesis 4.3.3).
#include <Eigen/Cholesky>

#include "null_space.h"

namespace cone_tracker {
namespace {

// Vertex j of eigenvector a as a 3-vector.
Eigen::Vector3d Vertex(const Matrix12d& V, int a, int j) { return V.block<3, 1>(3 * j, a); }

// βᵀQβ for (Σβ_a(v_a,i − v_a,k)) · (Σβ_b(v_b,j − v_b,k)) (4.125) (4.136).
QuadraticConstraint DotConstraint(const Matrix12d& V, int count, int i, int j, int k, double target) {
  QuadraticConstraint c;
  for (int a = 0; a < count; ++a)
    for (int b = 0; b < count; ++b) {
      const double v = (Vertex(V, a, i) - Vertex(V, a, k)).dot(Vertex(V, b, j) - Vertex(V, b, k));
      c.Q(a, b) += 0.5 * v;
      c.Q(b, a) += 0.5 * v;
    }
  c.target = target;
  return c;
}

}  // namespace

std::vector<QuadraticConstraint> DistanceConstraints(const Matrix12d& V, int count, const Vertices& model_vertices) {
  std::vector<QuadraticConstraint> out;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      // |P_i − P_j|² is the dot product of (P_i − P_j) with itself (4.124).
      out.push_back(DotConstraint(V, count, i, i, j, (model_vertices.col(i) - model_vertices.col(j)).squaredNorm()));
    }
  return out;
}

std::vector<QuadraticConstraint> DotProductConstraints(const Matrix12d& V, int count, const Vertices& model_vertices) {
  std::vector<QuadraticConstraint> out;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        if (i == k || j == k) continue;
        const double target =
            (model_vertices.col(i) - model_vertices.col(k)).dot(model_vertices.col(j) - model_vertices.col(k));
        out.push_back(DotConstraint(V, count, i, j, k, target));  // (4.135)
      }
  return out;
}

std::vector<QuadraticConstraint> TriadConstraints(const Matrix12d& V, int count) {
  std::vector<QuadraticConstraint> out;
  out.push_back(DotConstraint(V, count, 1, 2, 0, 0.0));  // legs orthogonal (4.138) (4.139)
  out.push_back(DotConstraint(V, count, 1, 3, 0, 0.0));
  out.push_back(DotConstraint(V, count, 2, 3, 0, 0.0));
  for (int k = 1; k < 4; ++k) out.push_back(DotConstraint(V, count, k, k, 0, 1.0));  // unit legs (4.140) (4.141)
  return out;
}

Eigen::Vector4d GaussNewtonBetas(const std::vector<QuadraticConstraint>& constraints, int count,
                                 const Eigen::Vector4d& beta0, int iterations) {
  Eigen::Vector4d beta = beta0;
  const int m = static_cast<int>(constraints.size());
  Eigen::MatrixXd J(m, count);
  Eigen::VectorXd f(m);
  for (int it = 0; it < iterations; ++it) {
    for (int l = 0; l < m; ++l) {
      const Eigen::Vector4d Qb = constraints[l].Q * beta;
      f(l) = beta.dot(Qb) - constraints[l].target;  // (4.131) (4.133)
      J.row(l) = 2.0 * Qb.head(count).transpose();  // (4.134)
    }
    const Eigen::VectorXd step = (J.transpose() * J).ldlt().solve(J.transpose() * f);  // (4.132)
    if (!step.allFinite()) break;
    beta.head(count) -= step;
    if (step.norm() <= 1e-14 * beta.norm()) break;
  }
  return beta;
}

Estimate PoseFromBetas(const Correspondences& c, const std::vector<PointMap>& maps, const Matrix12d& V,
                       const Eigen::Vector4d& beta, int count) {
  Vector12d vertices = Vector12d::Zero();
  for (int a = 0; a < count; ++a) vertices += beta(a) * V.col(a);  // (4.122)
  Eigen::Matrix3Xd camera = CameraPoints(maps, vertices);          // (4.123)
  if (camera.row(2).mean() < 0.0) camera = -camera;                // the sign ambiguity of (4.153)
  if (!camera.allFinite()) return Failure("non-finite eigenvector combination");
  Estimate e;
  e.ok = true;
  e.converged = true;
  e.T_camera_model = AbsoluteOrientationSvd(c.model, camera);
  return e;
}

}  // namespace cone_tracker

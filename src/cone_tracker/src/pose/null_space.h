// Shared machinery of the null-space algorithms (MDLT, 3-simplex, EPnP, SDP):
// a 12-vector v of unknowns maps to each camera point linearly, p_c,i = C_i v;
// image- or object-space null-space equations ((4.50) (4.51) or (4.52) (4.53) (4.54)) stack into a
// measurement matrix M with M v = 0 for noise-free data.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "cone_tracker/pose/algorithms.h"

namespace cone_tracker {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;
using PointMap = Eigen::Matrix<double, 3, 12>;  // C_i

// Rows of M for every point ((4.62) (4.63) (4.64) (4.65) (4.66) or (4.70) (4.71) (4.72) for the MDLT,
// (4.102) (4.103) or (4.104) (4.105) (4.106) for the simplex): image space fu(X − x Z), fv(Y − y Z)
// (pixels × depth); object space (F_i − I) p_c.
Eigen::MatrixXd MeasurementMatrix(const Correspondences& c, const std::vector<PointMap>& maps, ErrorSpace space);
// Eigenvectors V of MᵀM, smallest eigenvalue first (4.73), and the reduced
// measurement matrix M̂ = S Vᵀ with M̂ᵀM̂ = MᵀM (4.80).
struct NullSpace {
  Matrix12d V;
  Matrix12d reduced;
};
NullSpace DecomposeMeasurementMatrix(const Eigen::MatrixXd& M);
// Camera points C_i v for every i.
Eigen::Matrix3Xd CameraPoints(const std::vector<PointMap>& maps, const Vector12d& v);
// Scale β = sgn(Z̄) sqrt(Md / Cd) (4.76) (4.77) (4.78) and absolute orientation (4.79).
Estimate ScaleAndAlign(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& unscaled_camera);

// Gauss–Newton on f(Θ) = M̂ v(Θ) (4.85) (4.86) (4.87). Θ is a ZYX Euler-angle
// increment applied on the left of the current rotation plus the
// translation (4.83): R = Rz(α) Ry(β) Rx(γ) R_k, so the Euler singularity is
// never reached. `param` fills v and dv/dΘ (12×6) from R, t and the
// rotation derivatives dR/dα, dR/dβ, dR/dγ at Θ = 0.
using NullSpaceParam = void (*)(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Matrix3d dR[3],
                                Vector12d* v, Eigen::Matrix<double, 12, 6>* dv);
struct GaussNewtonResult {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  int iterations = 0;
  bool converged = false;
};
GaussNewtonResult NullSpaceGaussNewton(const Matrix12d& reduced, NullSpaceParam param, const Eigen::Matrix3d& R0,
                                       const Eigen::Vector3d& t0, int max_iterations);
// The two parameterisations: the MDLT's L = [R t] row-major (4.82) (4.84) and
// the 3-simplex's triad vertices [t, t + R e1, t + R e2, t + R e3] (4.116) (4.117).
void MdltParam(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Matrix3d dR[3], Vector12d* v,
               Eigen::Matrix<double, 12, 6>* dv);
void TriadParam(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Matrix3d dR[3], Vector12d* v,
                Eigen::Matrix<double, 12, 6>* dv);
// Rotation derivatives of the left Euler increment at zero: S(e_z) R, S(e_y) R, S(e_x) R.
void LeftEulerDerivatives(const Eigen::Matrix3d& R, Eigen::Matrix3d dR[3]);

// The unit orthogonal triad {S} on the model's principal axes (4.112).
struct Triad {
  Eigen::Matrix3d R_model_triad;         // M_S R (4.110) (4.111)
  Eigen::Vector3d centroid;              // M P̄m (4.109)
  Eigen::Matrix<double, 3, 4> vertices;  // M Ps (4.113)
  std::vector<PointMap> maps;            // from the barycentric coordinates (4.91)
};
bool MakeTriad(const Eigen::Matrix3Xd& model, Triad* triad);

// Barycentric coordinates of the model points w.r.t. four vertices (4.91);
// returns false if the vertices are coplanar.
bool Barycentric(const Eigen::Matrix<double, 3, 4>& vertices, const Eigen::Matrix3Xd& model, Eigen::Matrix4Xd* alpha);
std::vector<PointMap> SimplexPointMaps(const Eigen::Matrix4Xd& alpha);  // p_c,i = Σ_j α_ij Ps_j (4.94) (4.95) (4.96)

}  // namespace cone_tracker

namespace cone_tracker {

// A rotation- and translation-invariant quadratic shape constraint on a
// combination of null-space vectors, Σ β_a v_a (4.122): βᵀ Q β = target, with
// Q over up to four betas (unused rows/columns zero).
struct QuadraticConstraint {
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  double target = 0.0;
};
using Vertices = Eigen::Matrix<double, 3, 4>;
// Six vertex-pair distances (4.124) (4.125) (4.126).
std::vector<QuadraticConstraint> DistanceConstraints(const Matrix12d& V, int count, const Vertices& model_vertices);
// Twelve vertex-triplet dot products (4.135) (4.136) (4.137).
std::vector<QuadraticConstraint> DotProductConstraints(const Matrix12d& V, int count, const Vertices& model_vertices);
// Orthogonal unit triad: three right angles and three unit legs (4.138) (4.139) (4.140) (4.141).
std::vector<QuadraticConstraint> TriadConstraints(const Matrix12d& V, int count);
// Gauss–Newton on f_l(β) = βᵀQ_lβ − target_l (4.131) (4.132) (4.133) (4.134).
Eigen::Vector4d GaussNewtonBetas(const std::vector<QuadraticConstraint>& constraints, int count,
                                 const Eigen::Vector4d& beta0, int iterations);
// Vertices Σ β_a v_a in the camera, the model points from their barycentric
// maps, the sign that puts them in front, then absolute orientation (4.123).
Estimate PoseFromBetas(const Correspondences& c, const std::vector<PointMap>& maps, const Matrix12d& V,
                       const Eigen::Vector4d& beta, int count);

}  // namespace cone_tracker

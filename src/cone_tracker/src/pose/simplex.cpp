// 3-simplex + Gauss–Newton (thesis 4.3.2): the camera coordinates of the four
// vertices of a unit orthogonal triad {S} on the model's principal axes span
// the null space; Gauss–Newton moves the rigid triad.
#include <Eigen/Eigenvalues>

#include "null_space.h"

namespace cone_tracker {

bool MakeTriad(const Eigen::Matrix3Xd& model, Triad* triad) {
  triad->centroid = model.rowwise().mean();  // (4.109)
  // Principal directions (4.110): U of the SVD of the centred points, taken as
  // the eigenvectors of their 3×3 scatter matrix, largest first.
  const Eigen::Matrix3Xd centred = model.colwise() - triad->centroid;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(centred * centred.transpose());
  Eigen::Matrix3d R = eig.eigenvectors().rowwise().reverse();
  if (R.determinant() < 0.0) R.col(2) *= -1.0;  // det = +1 (4.111)
  triad->R_model_triad = R;
  Eigen::Matrix<double, 3, 4> vertices;  // (4.113)
  vertices.col(0) = triad->centroid;
  for (int k = 0; k < 3; ++k) vertices.col(k + 1) = triad->centroid + R.col(k);
  Eigen::Matrix4Xd alpha;
  if (!Barycentric(vertices, model, &alpha)) return false;
  triad->maps = SimplexPointMaps(alpha);
  triad->vertices = vertices;
  return true;
}

// Vertices of the triad in the camera from C_S R (4.116) and Ps1 = t (4.117).
void TriadParam(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Matrix3d dR[3], Vector12d* v,
                Eigen::Matrix<double, 12, 6>* dv) {
  v->head<3>() = t;
  for (int k = 0; k < 3; ++k) v->segment<3>(3 * (k + 1)) = t + R.col(k);
  if (dv == nullptr) return;
  dv->setZero();
  for (int j = 0; j < 4; ++j) dv->block<3, 3>(3 * j, 3).setIdentity();
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) dv->block<3, 1>(3 * (k + 1), a) = dR[a].col(k);
}

namespace {

Estimate Prepare(const Correspondences& c, Triad* triad) {
  if (c.size() < 6) return Failure("simplex needs at least 6 points");
  if (!MakeTriad(c.model, triad)) return Failure("simplex: degenerate triad");
  return Estimate{true, "", {}, 0, false, 0.0};
}

}  // namespace

Estimate SimplexLinear(const Correspondences& c, ErrorSpace space) {
  Triad triad;
  const Estimate check = Prepare(c, &triad);
  if (!check.ok) return check;
  const NullSpace ns = DecomposeMeasurementMatrix(MeasurementMatrix(c, triad.maps, space));  // (4.99)
  const Vector12d Ps = ns.V.col(0);                                                          // (4.107)
  return ScaleAndAlign(c.model, CameraPoints(triad.maps, Ps));                               // (4.108)
}

Estimate SimplexGaussNewton(const Correspondences& c, ErrorSpace space, const pose_math::Pose& initial,
                            int max_iterations) {
  Triad triad;
  const Estimate check = Prepare(c, &triad);
  if (!check.ok) return check;
  const Matrix12d reduced = DecomposeMeasurementMatrix(MeasurementMatrix(c, triad.maps, space)).reduced;
  const Eigen::Matrix3d R_cm = RotationOf(initial);
  const GaussNewtonResult gn = NullSpaceGaussNewton(reduced, &TriadParam, R_cm * triad.R_model_triad,
                                                    R_cm * triad.centroid + initial.t, max_iterations);  // (4.119)
  // C_M H = C_S H (M_S H)⁻¹ (4.120).
  const Eigen::Matrix3d R = gn.R * triad.R_model_triad.transpose();
  Estimate e;
  e.ok = true;
  e.T_camera_model = PoseFromRt(R, gn.t - R * triad.centroid);
  e.iterations = gn.iterations;
  e.converged = gn.converged;
  return e;
}

}  // namespace cone_tracker

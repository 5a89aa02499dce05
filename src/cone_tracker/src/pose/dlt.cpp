// Direct Linear Transform, Abdel-Aziz & Karara (thesis 4.2.2), on normalised image
// points with the intrinsics "clamped" to fu = fv = 1, u0 = v0 = 0.
#include <Eigen/QR>
#include <cmath>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/rotation.h"

namespace cone_tracker {

Estimate Dlt(const Correspondences& c) {
  const int n = c.size();
  if (n < 6) return Failure("dlt needs at least 6 points for its 11 parameters");
  Eigen::MatrixXd M(2 * n, 11);
  Eigen::VectorXd W(2 * n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = c.model.col(i);
    const double u = c.normalized(0, i), v = c.normalized(1, i);
    M.row(2 * i) << p.x(), p.y(), p.z(), 1.0, 0, 0, 0, 0, -u * p.x(), -u * p.y(), -u * p.z();  // (4.27)
    M.row(2 * i + 1) << 0, 0, 0, 0, p.x(), p.y(), p.z(), 1.0, -v * p.x(), -v * p.y(), -v * p.z();
    W(2 * i) = u;  // (4.30)
    W(2 * i + 1) = v;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(M);
  if (qr.rank() < 11) return Failure("dlt: the 11-parameter system is rank deficient (planar or degenerate points)");
  const Eigen::VectorXd L = qr.solve(W);  // least squares (4.31)
  if (!L.allFinite()) return Failure("dlt: non-finite solution");
  // In our convention p_c = R p_m + t, l1..l11 are the rows of [R t] divided
  // by tz, so with fu = fv = 1, u0 = v0 = 0 the thesis's R and t read R = D [l1 l2 l3;
  // l5 l6 l7; l9 l10 l11], t = D [l4 l8 1] with D² = 1/(l9² + l10² + l11²) (4.33).
  const Eigen::Vector3d r3(L(8), L(9), L(10));
  double D = 1.0 / r3.norm();
  // The sign of D puts the points in front of the camera: depth = D (l9..11·p + 1).
  double depth_sum = 0.0;
  for (int i = 0; i < n; ++i) depth_sum += r3.dot(c.model.col(i)) + 1.0;
  if (depth_sum < 0.0) D = -D;
  Eigen::Matrix3d R;
  R << L(0), L(1), L(2), L(4), L(5), L(6), L(8), L(9), L(10);
  R *= D;                                                          // (4.32)
  const Eigen::Vector3d t = D * Eigen::Vector3d(L(3), L(7), 1.0);  // (4.34) (4.35)
  Estimate e;
  e.rotation_nonorthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (R.determinant() <= 0.0) return Failure("dlt: the recovered rotation has a non-positive determinant");
  e.ok = true;
  e.converged = true;
  // The thesis leaves R non-orthogonal; a Pose needs a rotation, so report the
  // defect above and return the nearest rotation.
  e.T_camera_model = PoseFromRt(pose_math::NearestRotation(R), t);
  return e;
}

}  // namespace cone_tracker

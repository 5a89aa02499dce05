// Horn's absolute orientation (thesis 4.2.3): the rigid motion aligning model
// points with the same points estimated in the camera.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace cone_tracker {

pose_math::Pose AbsoluteOrientationSvd(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& camera) {
  const Eigen::Vector3d model_mean = model.rowwise().mean();  // (4.36)
  const Eigen::Vector3d camera_mean = camera.rowwise().mean();
  const Eigen::Matrix3d M = (camera.colwise() - camera_mean) * (model.colwise() - model_mean).transpose();  // (4.38)
  // U diag(1, 1, det(UVᵀ)) Vᵀ (4.39) (4.40), with the determinant fix of [40].
  const Eigen::Matrix3d R = pose_math::NearestRotation(M);
  return PoseFromRt(R, camera_mean - R * model_mean);  // (4.37)
}

pose_math::Pose AbsoluteOrientationQuat(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& camera) {
  const Eigen::Vector3d model_mean = model.rowwise().mean();
  const Eigen::Vector3d camera_mean = camera.rowwise().mean();
  // Σ (c ⊗ q)·(q ⊗ m) = qᵀ [Σ QL(c)ᵀ QR(m)] q for pure quaternions c, m (4.41).
  Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
  for (int i = 0; i < model.cols(); ++i) {
    pose_math::Quat c, m;
    c << 0.0, camera.col(i) - camera_mean;
    m << 0.0, model.col(i) - model_mean;
    N += pose_math::LeftMatrix(c).transpose() * pose_math::RightMatrix(m);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(0.5 * (N + N.transpose()));  // (4.42)
  const pose_math::Quat q = eig.eigenvectors().col(3);                                  // largest (4.43)
  pose_math::Pose T;
  T.q = pose_math::CanonicalSign(pose_math::NormalizedQuat(q));
  T.t = camera_mean - pose_math::RotationFromQuat(T.q) * model_mean;  // (4.37)
  return T;
}

}  // namespace cone_tracker

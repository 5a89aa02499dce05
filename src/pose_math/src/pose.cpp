#include "pose_math/pose.h"

#include <cmath>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"

namespace pose_math {

namespace {
// q* = C q.
Eigen::Matrix4d ConjugationMatrix() { return Eigen::Vector4d(1.0, -1.0, -1.0, -1.0).asDiagonal(); }

Matrix7d Propagate(const Matrix7d& J, const Matrix7d& cov) { return J * cov * J.transpose(); }

PoseWithCovariance OnTangent(const Pose& T, const Matrix7d& cov) {
  PoseWithCovariance out{T, ProjectToTangent(T.q, cov)};
  SymmetrizeCovariance(out.cov);
  return out;
}
}  // namespace

Vector7d ToVector(const Pose& T) {
  Vector7d theta;
  theta << T.q, T.t;
  return theta;
}

Pose FromVector(const Vector7d& theta) { return Pose{NormalizedQuat(theta.head<4>(), "FromVector"), theta.tail<3>()}; }

Eigen::Vector3d Transform(const Pose& T_a_b, const Eigen::Vector3d& p_b) { return Rotate(T_a_b.q, p_b) + T_a_b.t; }

Pose Invert(const Pose& T_a_b) {
  const Quat q_ba = Conjugate(NormalizedQuat(T_a_b.q, "Invert"));
  return Pose{q_ba, -Rotate(q_ba, T_a_b.t)};
}

Pose Compose(const Pose& T_a_b, const Pose& T_b_c) {
  const Quat q_ab = NormalizedQuat(T_a_b.q, "Compose");
  const Quat q_ac = Multiply(q_ab, NormalizedQuat(T_b_c.q, "Compose"));
  return Pose{NormalizedQuat(q_ac, "Compose"), Rotate(q_ab, T_b_c.t) + T_a_b.t};
}

Matrix7d InvertJacobian(const Pose& T_a_b) {
  const Quat q_ba = Conjugate(NormalizedQuat(T_a_b.q, "InvertJacobian"));
  const Eigen::Matrix4d C = ConjugationMatrix();
  Matrix7d J = Matrix7d::Zero();
  J.topLeftCorner<4, 4>() = C;
  J.bottomLeftCorner<3, 4>() = -RotateJacobianWrtQuat(q_ba, T_a_b.t) * C;
  J.bottomRightCorner<3, 3>() = -RotationFromQuat(q_ba);
  return J;
}

void ComposeJacobians(const Pose& T_a_b, const Pose& T_b_c, Matrix7d* J_wrt_ab, Matrix7d* J_wrt_bc) {
  const Quat q_ab = NormalizedQuat(T_a_b.q, "ComposeJacobians");
  const Quat q_bc = NormalizedQuat(T_b_c.q, "ComposeJacobians");
  if (J_wrt_ab != nullptr) {
    J_wrt_ab->setZero();
    J_wrt_ab->topLeftCorner<4, 4>() = RightMatrix(q_bc);  // q_ab ⊗ q_bc = QR(q_bc) q_ab (2.44)
    J_wrt_ab->bottomLeftCorner<3, 4>() = RotateJacobianWrtQuat(q_ab, T_b_c.t);
    J_wrt_ab->bottomRightCorner<3, 3>().setIdentity();
  }
  if (J_wrt_bc != nullptr) {
    J_wrt_bc->setZero();
    J_wrt_bc->topLeftCorner<4, 4>() = LeftMatrix(q_ab);  // = QL(q_ab) q_bc
    J_wrt_bc->bottomRightCorner<3, 3>() = RotationFromQuat(q_ab);
  }
}

PoseWithCovariance Invert(const PoseWithCovariance& T_a_b) {
  return OnTangent(Invert(T_a_b.pose), Propagate(InvertJacobian(T_a_b.pose), T_a_b.cov));
}

PoseWithCovariance Compose(const PoseWithCovariance& T_a_b, const PoseWithCovariance& T_b_c) {
  Matrix7d J_ab, J_bc;
  ComposeJacobians(T_a_b.pose, T_b_c.pose, &J_ab, &J_bc);
  return OnTangent(Compose(T_a_b.pose, T_b_c.pose), Propagate(J_ab, T_a_b.cov) + Propagate(J_bc, T_b_c.cov));
}

Pose ExtrapolateConstantRate(const Pose& T_a_b_prev, double t_prev_s, const Pose& T_a_b_new, double t_new_s,
                             double t_s) {
  const double span_s = t_new_s - t_prev_s;
  if (!(span_s > 0.0)) return T_a_b_new;
  const double s = (t_s - t_new_s) / span_s;
  // R_new = R_prev Exp(r): r is the body-frame rotation over the span, applied again s times.
  const Eigen::Vector3d r = RotationVectorFromQuat(Multiply(Conjugate(T_a_b_prev.q), T_a_b_new.q));
  return {NormalizedQuat(Multiply(T_a_b_new.q, QuatFromRotationVector(s * r)), "ExtrapolateConstantRate"),
          T_a_b_new.t + s * (T_a_b_new.t - T_a_b_prev.t)};
}

double RotationErrorRad(const Pose& a, const Pose& b) {
  const Quat d = Multiply(Conjugate(NormalizedQuat(a.q, "RotationErrorRad")), NormalizedQuat(b.q, "RotationErrorRad"));
  return 2.0 * std::atan2(d.tail<3>().norm(), std::abs(d[0]));
}

double TranslationError(const Pose& a, const Pose& b) { return (a.t - b.t).norm(); }

}  // namespace pose_math

// Modified DLT + Gauss–Newton (thesis 4.3.1): the 12 coefficients of an
// unconstrained linear transform L = [R t] (4.55) (4.56) span the null space of
// the measurement matrix; scale and absolute orientation make it a pose, and
// Gauss–Newton on the reduced 12×12 matrix enforces the rotation.
#include "null_space.h"

namespace cone_tracker {
namespace {

// p_c = L [p; 1] with L row-major in v (4.56).
std::vector<PointMap> MdltPointMaps(const Eigen::Matrix3Xd& model) {
  std::vector<PointMap> maps(model.cols());
  for (int i = 0; i < model.cols(); ++i) {
    maps[i].setZero();
    for (int r = 0; r < 3; ++r) {
      maps[i].block<1, 3>(r, 4 * r) = model.col(i).transpose();
      maps[i](r, 4 * r + 3) = 1.0;
    }
  }
  return maps;
}

}  // namespace

// L(Θ) = [R(Θ) t(Θ)] (4.82) over Θ = [α β γ tx ty tz] (4.83), row-major (4.84).
void MdltParam(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Matrix3d dR[3], Vector12d* v,
               Eigen::Matrix<double, 12, 6>* dv) {
  for (int r = 0; r < 3; ++r) {
    v->segment<3>(4 * r) = R.row(r).transpose();
    (*v)(4 * r + 3) = t(r);
  }
  if (dv == nullptr) return;
  dv->setZero();
  for (int k = 0; k < 3; ++k)
    for (int r = 0; r < 3; ++r) dv->block<3, 1>(4 * r, k) = dR[k].row(r).transpose();
  for (int r = 0; r < 3; ++r) (*dv)(4 * r + 3, 3 + r) = 1.0;
}

namespace {

Estimate CheckPoints(const Correspondences& c, const char* name) {
  if (c.size() < 6) return Failure(std::string(name) + " needs at least 6 points");
  return Estimate{true, "", {}, 0, false, 0.0};
}

}  // namespace

Estimate MdltLinear(const Correspondences& c, ErrorSpace space) {
  const Estimate check = CheckPoints(c, "mdlt");
  if (!check.ok) return check;
  const std::vector<PointMap> maps = MdltPointMaps(c.model);
  const NullSpace ns = DecomposeMeasurementMatrix(MeasurementMatrix(c, maps, space));  // (4.69) (4.73)
  const Vector12d L = ns.V.col(0);                                                     // (4.74)
  return ScaleAndAlign(c.model, CameraPoints(maps, L));                                // (4.75)
}

Estimate MdltGaussNewton(const Correspondences& c, ErrorSpace space, const pose_math::Pose& initial,
                         int max_iterations) {
  const Estimate check = CheckPoints(c, "mdlt");
  if (!check.ok) return check;
  const Matrix12d reduced = DecomposeMeasurementMatrix(MeasurementMatrix(c, MdltPointMaps(c.model), space)).reduced;
  const GaussNewtonResult gn =
      NullSpaceGaussNewton(reduced, &MdltParam, RotationOf(initial), initial.t, max_iterations);
  Estimate e;
  e.ok = true;
  e.T_camera_model = PoseFromRt(gn.R, gn.t);
  e.iterations = gn.iterations;
  e.converged = gn.converged;
  return e;
}

}  // namespace cone_tracker

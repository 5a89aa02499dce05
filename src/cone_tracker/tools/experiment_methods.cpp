#include "experiment_methods.h"

#include "opencv_baseline.h"

namespace cone_tracker {
namespace experiments {
namespace {

using Linear = std::function<Estimate(const Correspondences&)>;

bool Take(const Estimate& e, pose_math::Pose* T) {
  if (!e.ok) return false;
  *T = e.T_camera_model;
  return T->q.allFinite() && T->t.allFinite();
}

Method Single(const std::string& name, const Linear& f) {
  return {name, [f](const Trial& t, pose_math::Pose* T) { return Take(f(t.c), T); }};
}

// Linear start followed by a refinement from it.
Method Chain(const std::string& name, const Linear& start,
             const std::function<Estimate(const Correspondences&, const pose_math::Pose&)>& refine) {
  return {name, [start, refine](const Trial& t, pose_math::Pose* T) {
            const Estimate s = start(t.c);
            return s.ok && Take(refine(t.c, s.T_camera_model), T);
          }};
}

Linear MdltLin(ErrorSpace s) {
  return [s](const Correspondences& c) { return MdltLinear(c, s); };
}
Linear SimplexLin(ErrorSpace s) {
  return [s](const Correspondences& c) { return SimplexLinear(c, s); };
}
auto Oia() {
  return [](const Correspondences& c, const pose_math::Pose& T) { return OrthogonalIteration(c, &T, 200, 1e-12); };
}
auto MdltGn(ErrorSpace s) {
  return [s](const Correspondences& c, const pose_math::Pose& T) { return MdltGaussNewton(c, s, T); };
}
auto SimplexGn(ErrorSpace s) {
  return [s](const Correspondences& c, const pose_math::Pose& T) { return SimplexGaussNewton(c, s, T); };
}
auto FullCeres() {
  return [](const Correspondences& c, const pose_math::Pose& T) { return CeresRefine(c, T, false, 2.0, 100); };
}

void AddComparison(std::vector<Method>* methods) {
  methods->push_back(Method{"best", [](const Trial& t, pose_math::Pose* T) {
                              PnpOptions o;
                              o.compute_covariance = false;
                              o.sigma_px = t.sigma_px;
                              const PnpResult r = SolvePnp(t.truth.camera, t.truth.model, t.noisy_px, o);
                              *T = r.T_camera_model;
                              return r.ok;
                            }});
  methods->push_back(Chain("Simplex+Ceres", SimplexLin(ErrorSpace::kImage), FullCeres()));
  for (const auto& m : baseline::OpenCvMethods()) {
    const int flag = m.flag;
    methods->push_back(Method{m.name, [flag](const Trial& t, pose_math::Pose* T) {
                                return baseline::SolveOpenCv(flag, t.truth.camera, t.truth.model, t.noisy_px, T);
                              }});
  }
}

}  // namespace

Trial MakeTrial(sim::Case truth, std::vector<Eigen::Vector2d> noisy_px, double sigma_px) {
  Trial t{std::move(truth), std::move(noisy_px), {}, sigma_px};
  const int n = static_cast<int>(t.truth.model.size());
  t.c.fx_px = t.truth.camera.fx_px;
  t.c.fy_px = t.truth.camera.fy_px;
  t.c.model.resize(3, n);
  t.c.normalized.resize(2, n);
  for (int i = 0; i < n; ++i) {
    t.c.model.col(i) = t.truth.model[i];
    t.c.normalized.col(i) << (t.noisy_px[i].x() - t.truth.camera.cx_px) / t.truth.camera.fx_px,
        (t.noisy_px[i].y() - t.truth.camera.cy_px) / t.truth.camera.fy_px;
  }
  return t;
}

std::vector<Method> GroupMethods(int group) {
  const ErrorSpace IS = ErrorSpace::kImage, OS = ErrorSpace::kObject;
  std::vector<Method> m;
  const auto sdp = [](ErrorSpace s) {
    return [s](const Correspondences& c) { return SimplexSdp(c, s, 4, PnpOptions::SdpConstraint::kDistance); };
  };
  switch (group) {
    case 1:
      m = {Single("DLT", Dlt), Single("MDLT (IS)", MdltLin(IS)), Single("MDLT (OS)", MdltLin(OS)),
           Single("3-Simplex (IS)", SimplexLin(IS)), Single("3-Simplex (OS)", SimplexLin(OS))};
      break;
    case 2:
      m = {Single("EPnP (v1)", EpnpLinear), Single("EPnP (v2)", EpnpGaussNewton), Single("3-Simplex SDP (IS)", sdp(IS)),
           Single("3-Simplex SDP (OS)", sdp(OS))};
      break;
    case 3:
    case 4: {
      const ErrorSpace s = group == 3 ? IS : OS;
      const std::string tag = group == 3 ? " (IS)" : " (OS)";
      m = {Chain("MDLT + OIA" + tag, MdltLin(s), Oia()), Chain("3-Simplex + OIA" + tag, SimplexLin(s), Oia()),
           Chain("MDLT + GN" + tag, MdltLin(s), MdltGn(s)), Chain("3-Simplex + GN" + tag, SimplexLin(s), SimplexGn(s))};
      break;
    }
    case 5:
      m = {Chain("3-Simplex + OIA (IS)", SimplexLin(IS), Oia()), Chain("3-Simplex + OIA (OS)", SimplexLin(OS), Oia()),
           Chain("3-Simplex + GN (IS)", SimplexLin(IS), SimplexGn(IS)),
           Chain("3-Simplex + GN (OS)", SimplexLin(OS), SimplexGn(OS))};
      break;
    default:
      break;
  }
  AddComparison(&m);
  return m;
}

std::vector<Method> ConeMethods() {
  std::vector<Method> m = {Chain("3-Simplex + OIA (IS)", SimplexLin(ErrorSpace::kImage), Oia()),
                           Chain("3-Simplex + GN (IS)", SimplexLin(ErrorSpace::kImage), SimplexGn(ErrorSpace::kImage))};
  AddComparison(&m);
  return m;
}

}  // namespace experiments
}  // namespace cone_tracker

// 3-simplex SDP (thesis 4.3.3 and appendix 9.2): the triad's camera vertices as a
// combination of the 2, 3 or 4 null-space eigenvectors of smallest eigenvalue
// (4.121) (4.122), the betas from the polynomial SDP on distance, dot-product or
// orthogonal-triad constraints, then absolute orientation (4.123).
#include "moment_sdp.h"
#include "null_space.h"

namespace cone_tracker {

Estimate SimplexSdp(const Correspondences& c, ErrorSpace space, int eigenvectors,
                    PnpOptions::SdpConstraint constraint) {
  if (c.size() < 6) return Failure("simplex-sdp needs at least 6 points");
  if (eigenvectors < 2 || eigenvectors > 4) return Failure("simplex-sdp uses 2, 3 or 4 eigenvectors");
  Triad triad;
  if (!MakeTriad(c.model, &triad)) return Failure("simplex-sdp: degenerate triad");
  const Matrix12d V = DecomposeMeasurementMatrix(MeasurementMatrix(c, triad.maps, space)).V;
  std::vector<QuadraticConstraint> constraints;
  switch (constraint) {
    case PnpOptions::SdpConstraint::kDistance:
      constraints = DistanceConstraints(V, eigenvectors, triad.vertices);
      break;
    case PnpOptions::SdpConstraint::kDotProduct:
      constraints = DotProductConstraints(V, eigenvectors, triad.vertices);
      break;
    case PnpOptions::SdpConstraint::kOrthogonalTriad:
      constraints = TriadConstraints(V, eigenvectors);
      break;
  }
  Eigen::Vector4d beta;
  std::string error;
  if (!SolveMomentRelaxation(constraints, eigenvectors, &beta, &error)) return Failure(error);
  // The SDP is solved to the solver's tolerance (~1e-8); a few Gauss–Newton
  // steps (4.132) on the same constraints polish the betas.
  const Eigen::Vector4d polished = GaussNewtonBetas(constraints, eigenvectors, beta, 5);
  Estimate e = PoseFromBetas(c, triad.maps, V, polished.allFinite() ? polished : beta, eigenvectors);
  e.iterations = 5;
  return e;
}

}  // namespace cone_tracker

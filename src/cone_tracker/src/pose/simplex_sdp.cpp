#include "null_space.h"
namespace cone_tracker {
Estimate SimplexSdp(const Correspondences&, ErrorSpace, int, PnpOptions::SdpConstraint) {
  return Failure("simplex-sdp: not implemented yet");
}
}  // namespace cone_tracker

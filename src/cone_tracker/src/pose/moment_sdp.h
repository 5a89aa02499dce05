// The polynomial SDP of thesis 4.3.3.5 (Lasserre's moment relaxation, solved
// with CSDP): minimise Σ_l (βᵀQ_lβ − d_l)² over up to four betas.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "null_space.h"

namespace cone_tracker {

// Returns false (with a reason) if CSDP fails. beta gets the recovered
// betas (4.153), up to the global sign fixed later by the depth.
bool SolveMomentRelaxation(const std::vector<QuadraticConstraint>& constraints, int count, Eigen::Vector4d* beta,
                           std::string* error);

}  // namespace cone_tracker

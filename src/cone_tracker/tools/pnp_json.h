// JSON lines for pnp_solve: one case in, one result out (formats in pnp_solve.cpp).
#pragma once
#include <nlohmann/json.hpp>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/pose/ransac.h"

namespace cone_tracker {
// Solves one case. Malformed input gives {"ok": false, "error": ...}; never throws.
// Output keys keep the documented order (ordered_json). With ransac, SolvePnpRansac (ransac.h) solves
// it, and the output adds "inliers" (their number) and "outliers" (the input indices of the rest).
nlohmann::ordered_json SolveJsonCase(const nlohmann::json& in, PnpOptions options,
                                     const RansacOptions* ransac = nullptr);
}  // namespace cone_tracker

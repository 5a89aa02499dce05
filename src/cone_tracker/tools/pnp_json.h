// JSON lines for pnp_solve: one case in, one result out (formats in pnp_solve.cpp).
#pragma once
#include <nlohmann/json.hpp>

#include "cone_tracker/pose/pnp.h"

namespace cone_tracker {
// Solves one case. Malformed input gives {"ok": false, "error": ...}; never throws.
// Output keys keep the documented order (ordered_json).
nlohmann::ordered_json SolveJsonCase(const nlohmann::json& in, PnpOptions options);
}  // namespace cone_tracker

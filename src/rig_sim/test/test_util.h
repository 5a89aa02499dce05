#pragma once

#include <string>

#include "rig_sim/scenario.h"

namespace rig_sim {

inline std::string LayoutsDir() { return RIG_SIM_LAYOUTS_DIR; }

// A scenario for tests: shortened, with a small image.
inline Scenario TestScenario(const std::string& name, uint64_t seed, double duration_s, double scale) {
  Scenario s;
  std::string err;
  if (!MakeScenario(name, seed, LayoutsDir(), &s, &err)) throw std::runtime_error(err);
  ShortenScenario(duration_s, scale, &s);
  return s;
}

}  // namespace rig_sim

// Angle constants of rig_sim's core sources (internal to rig_sim), defined once: a target's sources
// may share one translation unit in a unity build (cmake/workspace.cmake).
#pragma once

namespace rig_sim {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;  // radians per degree

}  // namespace rig_sim

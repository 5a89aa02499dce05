#pragma once
#include <ostream>

namespace cone_tracker {
namespace experiments {
// The camera-uncertainty check of 7.1.3: one pose and 25 points, σ = 5, 7.5
// and 10 px, `trials` noise draws each, image and object space, Euler and
// quaternion. Prints tables shaped like figures 7.3–7.6 with the thesis's
// numbers beside ours, to both streams.
void MonteCarloTables(int trials, std::ostream& out, std::ostream& copy);
}  // namespace experiments
}  // namespace cone_tracker

// Test helpers around PseudoTerminal: paced writes and waiting for a condition.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

#include "imu_driver/core/pseudo_terminal.h"

namespace imu_driver {
namespace test {

class PtyWriter : public PseudoTerminal {
 public:
  using PseudoTerminal::PseudoTerminal;
  // Writes the stream in chunks of about one frame, one every period (100 Hz).
  void WritePaced(const std::vector<uint8_t>& bytes, size_t chunk = 26, double period_s = 0.01) {
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0, k = 1; i < bytes.size(); i += chunk, ++k) {
      Write(&bytes[i], std::min(chunk, bytes.size() - i));
      std::this_thread::sleep_until(start + std::chrono::duration<double>(k * period_s));
    }
  }
};

// Polls cond every 5 ms; false after timeout_s (a hang guard, not a speed limit: generous for a loaded machine).
inline bool WaitFor(const std::function<bool()>& cond, double timeout_s = 60.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until) {
    if (cond()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return cond();
}

}  // namespace test
}  // namespace imu_driver

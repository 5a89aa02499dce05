// Test-only stand-in for the IMU: a pseudo-terminal whose slave is reachable
// through a fixed symlink (like /dev/serial/by-id/...), so "unplug" and
// "replug" are: close the master, open a new pty, re-point the link.
#pragma once

#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace imu_driver {
namespace test {

class PtyWriter {
 public:
  explicit PtyWriter(std::string link) : link_(std::move(link)) {}
  ~PtyWriter() { Unplug(); }

  void Plug() {
    Unplug();
    termios tio{};
    ::cfmakeraw(&tio);
    int slave = -1;
    char name[256] = {};
    if (::openpty(&master_, &slave, name, &tio, nullptr) != 0) throw std::runtime_error("openpty failed");
    ::close(slave);  // only the driver holds the slave open
    const std::string tmp = link_ + ".new";
    ::unlink(tmp.c_str());
    if (::symlink(name, tmp.c_str()) != 0 || ::rename(tmp.c_str(), link_.c_str()) != 0) {
      throw std::runtime_error("cannot link " + link_);
    }
  }
  void Unplug() {
    if (master_ >= 0) ::close(master_);
    master_ = -1;
  }
  void Write(const uint8_t* d, size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(master_, d, n);
      if (w <= 0) throw std::runtime_error("pty write failed");
      d += w;
      n -= static_cast<size_t>(w);
    }
  }
  // Writes the stream in chunks of about one frame, one every period (100 Hz).
  void WritePaced(const std::vector<uint8_t>& bytes, size_t chunk = 26, double period_s = 0.01) {
    for (size_t i = 0; i < bytes.size(); i += chunk) {
      Write(&bytes[i], std::min(chunk, bytes.size() - i));
      std::this_thread::sleep_for(std::chrono::duration<double>(period_s));
    }
  }

 private:
  std::string link_;
  int master_ = -1;
};

// Polls cond every 5 ms; false after timeout_s (a failure deadline, not a speed limit).
inline bool WaitFor(const std::function<bool()>& cond, double timeout_s = 10.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until) {
    if (cond()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return cond();
}

}  // namespace test
}  // namespace imu_driver

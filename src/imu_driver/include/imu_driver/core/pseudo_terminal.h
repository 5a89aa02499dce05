// A stand-in serial device for simulators and tests: a pseudo-terminal whose
// slave is reachable through a fixed symlink (like /dev/serial/by-id/...), so
// "unplug" and "replug" are: close the master; open a new pty and re-point the link.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace imu_driver {

class PseudoTerminal {
 public:
  explicit PseudoTerminal(std::string link) : link_(std::move(link)) {}
  ~PseudoTerminal() { Unplug(); }
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  // Opens a raw-mode pty and points the link at its slave. Throws std::runtime_error.
  void Plug();
  // Closes the master: a reader of the slave gets EIO, like an unplugged USB adapter.
  void Unplug();
  // Writes everything (blocking). Throws std::runtime_error when the pty is gone.
  void Write(const uint8_t* data, size_t n);
  // Like a real IMU, which sends whether or not anyone listens: returns false
  // (and writes nothing) when the pty's buffer is full.
  bool WriteIfRoom(const uint8_t* data, size_t n);
  // What the reader sent to the device: up to capacity bytes, waiting up to timeout_ms.
  size_t Read(uint8_t* buf, size_t capacity, int timeout_ms);
  const std::string& link() const { return link_; }
  const std::string& slave_name() const { return slave_name_; }

 private:
  std::string link_;
  std::string slave_name_;
  int master_ = -1;
};

}  // namespace imu_driver

#include "imu_driver/core/pseudo_terminal.h"

#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace imu_driver {

void PseudoTerminal::Plug() {
  Unplug();
  termios tio{};
  ::cfmakeraw(&tio);
  int slave = -1;
  char name[256] = {};
  if (::openpty(&master_, &slave, name, &tio, nullptr) != 0) {
    throw std::runtime_error(std::string("openpty: ") + std::strerror(errno));
  }
  ::close(slave);  // only the reader holds the slave open
  slave_name_ = name;
  const std::string tmp = link_ + ".new";
  ::unlink(tmp.c_str());
  if (::symlink(name, tmp.c_str()) != 0 || ::rename(tmp.c_str(), link_.c_str()) != 0) {
    throw std::runtime_error("cannot link " + link_ + " to " + name + ": " + std::strerror(errno));
  }
}

void PseudoTerminal::Unplug() {
  if (master_ < 0) return;
  // The link goes first, as udev removes /dev/ttyUSB0 on unplug: the pty number
  // is reused by the next openpty anywhere on the machine, and a reader that
  // reopened a stale link could end up on someone else's pty.
  ::unlink(link_.c_str());
  ::close(master_);
  master_ = -1;
}

void PseudoTerminal::Write(const uint8_t* d, size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(master_, d, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw std::runtime_error(std::string("pty write: ") + std::strerror(errno));
    d += w;
    n -= static_cast<size_t>(w);
  }
}

bool PseudoTerminal::WriteIfRoom(const uint8_t* data, size_t n) {
  pollfd p{master_, POLLOUT, 0};
  if (master_ < 0 || ::poll(&p, 1, 0) <= 0 || !(p.revents & POLLOUT)) return false;
  Write(data, n);
  return true;
}

size_t PseudoTerminal::Read(uint8_t* buf, size_t capacity, int timeout_ms) {
  pollfd p{master_, POLLIN, 0};
  if (master_ < 0 || ::poll(&p, 1, timeout_ms) <= 0 || !(p.revents & POLLIN)) return 0;
  const ssize_t n = ::read(master_, buf, capacity);
  return n > 0 ? static_cast<size_t>(n) : 0;
}

}  // namespace imu_driver

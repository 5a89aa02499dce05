#include "imu_driver/core/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace imu_driver {
namespace {

std::string SysError(const std::string& what, int err) { return what + ": " + std::strerror(err); }

bool IsDisconnect(int err) { return err == EIO || err == ENXIO || err == ENODEV || err == EBADF; }

}  // namespace

unsigned BaudToSpeed(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 921600:
      return B921600;
    default:
      return 0;
  }
}

bool SerialPort::Open(const std::string& path, int baud, std::string* error) {
  Close();
  const speed_t speed = BaudToSpeed(baud);
  if (speed == 0) {
    *error = "unsupported baud rate " + std::to_string(baud);
    return false;
  }
  // O_NONBLOCK: never hang in open() on modem control lines; reads use poll().
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *error = SysError("cannot open " + path, errno);
    return false;
  }
  // Two readers on one port would each get half the bytes: take the port
  // exclusively (flock for other processes of ours, TIOCEXCL for the rest).
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    *error = SysError(path + " is in use by another process", errno);
    ::close(fd);
    return false;
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) {
    *error = SysError(path + " is not a serial device (tcgetattr)", errno);
    ::close(fd);
    return false;
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | CRTSCTS | PARENB);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0 || ::tcsetattr(fd, TCSANOW, &tio) != 0) {
    *error = SysError("cannot configure " + path + " at " + std::to_string(baud) + " baud", errno);
    ::close(fd);
    return false;
  }
  ::ioctl(fd, TIOCEXCL);    // best effort: refused silently by some drivers
  ::tcflush(fd, TCIFLUSH);  // bytes queued before we were ready are of unknown age
  fd_ = fd;
  path_ = path;
  return true;
}

void SerialPort::Close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SerialPort::Write(const uint8_t* data, size_t n, int timeout_ms, std::string* error) {
  while (n > 0) {
    pollfd p{fd_, POLLOUT, 0};
    if (fd_ < 0 || ::poll(&p, 1, timeout_ms) <= 0) {
      *error = "write " + path_ + ": timed out or port closed";
      return false;
    }
    const ssize_t w = ::write(fd_, data, n);
    if (w < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (w <= 0) {
      *error = SysError("write " + path_, errno);
      return false;
    }
    data += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}

SerialPort::ReadResult SerialPort::Read(uint8_t* buf, size_t capacity, int timeout_ms) {
  ReadResult r;
  if (fd_ < 0) {
    r.status = ReadStatus::kDisconnected;
    r.error = "port not open";
    return r;
  }
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return r;
    r.status = ReadStatus::kError;
    r.error = SysError("poll " + path_, errno);
    return r;
  }
  if (ready == 0) return r;
  const ssize_t n = ::read(fd_, buf, capacity);
  if (n > 0) {
    r.status = ReadStatus::kData;
    r.bytes = static_cast<size_t>(n);
    return r;
  }
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return r;
  // n == 0 after POLLIN/POLLHUP, or EIO: the device is gone (USB unplugged,
  // pty master closed).
  const int err = n < 0 ? errno : EIO;
  r.status = (n == 0 || IsDisconnect(err)) ? ReadStatus::kDisconnected : ReadStatus::kError;
  r.error = SysError("read " + path_, err);
  return r;
}

}  // namespace imu_driver

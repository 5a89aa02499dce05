// A serial device in termios raw mode (8N1, no flow control, no echo, no line
// editing). Works the same on a USB-serial adapter and on a pseudo-terminal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace imu_driver {

// termios speed constant for a baud rate, or 0 when the rate is not supported.
unsigned BaudToSpeed(int baud);

class SerialPort {
 public:
  enum class ReadStatus { kData, kTimeout, kDisconnected, kError };
  struct ReadResult {
    ReadStatus status = ReadStatus::kTimeout;
    size_t bytes = 0;
    std::string error;  // for kDisconnected and kError
  };

  SerialPort() = default;
  ~SerialPort() { Close(); }
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Opens and configures path; on failure returns false and sets *error
  // (naming the path and the system error).
  bool Open(const std::string& path, int baud, std::string* error);
  void Close();
  bool is_open() const { return fd_ >= 0; }

  // Waits up to timeout_ms for bytes. kDisconnected when the device went away
  // (EIO, ENXIO, ENODEV, hang-up): the caller closes and reopens.
  ReadResult Read(uint8_t* buf, size_t capacity, int timeout_ms);
  // Writes all bytes, waiting up to timeout_ms for room; false with *error otherwise.
  bool Write(const uint8_t* data, size_t n, int timeout_ms, std::string* error);

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace imu_driver

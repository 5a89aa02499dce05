#include "rig_sim/crista.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

namespace rig_sim {
namespace {

void PutBe16(int16_t v, std::vector<uint8_t>* out) {
  const uint16_t u = static_cast<uint16_t>(v);
  out->push_back(static_cast<uint8_t>(u >> 8));
  out->push_back(static_cast<uint8_t>(u & 0xFF));
}

}  // namespace

uint16_t Crc16Arc(const uint8_t* data, size_t size) {
  // 16-entry nibble table of the reflected polynomial 0xA001.
  static const uint16_t kTable[16] = {0x0000, 0xCC01, 0xD801, 0x1400, 0xF001, 0x3C00, 0x2800, 0xE401,
                                      0xA001, 0x6C00, 0x7800, 0xB401, 0x5000, 0x9C01, 0x8801, 0x4400};
  uint16_t crc = 0;
  for (size_t i = 0; i < size; ++i) {
    crc = static_cast<uint16_t>((crc >> 4) ^ kTable[(crc ^ data[i]) & 0x0F]);
    crc = static_cast<uint16_t>((crc >> 4) ^ kTable[(crc ^ (data[i] >> 4)) & 0x0F]);
  }
  return crc;
}

std::vector<uint8_t> EncodeCristaHighSpeed(const ImuSample& s, uint32_t time_since_pps_us, uint8_t pps_count,
                                           uint8_t sequence) {
  std::vector<uint8_t> p = {kCristaSync0, kCristaSync1, kCristaTypeHighSpeed,
                            static_cast<uint8_t>(kCristaHighSpeedPayload)};
  p.reserve(kCristaHighSpeedPacket);
  for (int i = 0; i < 3; ++i) PutBe16(s.gyro_raw[i], &p);
  for (int i = 0; i < 3; ++i) PutBe16(s.accel_raw[i], &p);
  for (int shift = 24; shift >= 0; shift -= 8) p.push_back(static_cast<uint8_t>(time_since_pps_us >> shift));
  p.push_back(pps_count);
  p.push_back(sequence);
  const uint16_t crc = Crc16Arc(p.data(), p.size());
  p.push_back(static_cast<uint8_t>(crc >> 8));
  p.push_back(static_cast<uint8_t>(crc & 0xFF));
  return p;
}

CristaPty::CristaPty() {
  master_fd_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (master_fd_ < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
  char name[128];
  if (grantpt(master_fd_) != 0 || unlockpt(master_fd_) != 0 || ptsname_r(master_fd_, name, sizeof(name)) != 0) {
    const std::string err = std::strerror(errno);
    close(master_fd_);
    throw std::runtime_error("preparing the pseudo-terminal: " + err);
  }
  slave_path_ = name;
  slave_fd_ = open(name, O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (slave_fd_ >= 0) {
    termios tio;
    if (tcgetattr(slave_fd_, &tio) == 0) {
      cfmakeraw(&tio);
      cfsetispeed(&tio, B115200);
      cfsetospeed(&tio, B115200);
      tcsetattr(slave_fd_, TCSANOW, &tio);
    }
  }
}

CristaPty::~CristaPty() {
  if (!link_path_.empty()) unlink(link_path_.c_str());
  if (slave_fd_ >= 0) close(slave_fd_);
  if (master_fd_ >= 0) close(master_fd_);
}

bool CristaPty::Link(const std::string& link_path, std::string* error) {
  struct stat st;
  if (lstat(link_path.c_str(), &st) == 0) {
    if (!S_ISLNK(st.st_mode)) {
      if (error) *error = link_path + " exists and is not a symlink; not replacing it";
      return false;
    }
    unlink(link_path.c_str());
  }
  if (symlink(slave_path_.c_str(), link_path.c_str()) != 0) {
    if (error) *error = "symlink " + link_path + ": " + std::strerror(errno);
    return false;
  }
  link_path_ = link_path;
  return true;
}

bool CristaPty::Write(const std::vector<uint8_t>& bytes) {
  const ssize_t n = write(master_fd_, bytes.data(), bytes.size());
  if (n == static_cast<ssize_t>(bytes.size())) return true;
  ++dropped_;  // buffer full (nobody reading) or a partial write: the reader resyncs on 0x55 0xAA
  return false;
}

}  // namespace rig_sim

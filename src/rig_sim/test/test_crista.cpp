#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include "rig_sim/crista.h"

namespace rig_sim {

TEST(Crista, Crc16ArcKnownValue) {
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(Crc16Arc(check, sizeof(check)), 0xBB3D);  // the CRC-16/ARC check value
  EXPECT_EQ(Crc16Arc(check, 0), 0x0000);
}

TEST(Crista, HighSpeedPacketLayout) {
  ImuSample s;
  s.gyro_raw[0] = 1;
  s.gyro_raw[1] = -2;
  s.gyro_raw[2] = 0x1234;
  s.accel_raw[0] = -32768;
  s.accel_raw[1] = 32767;
  s.accel_raw[2] = 3278;  // ~ +1 g: 9.81 m/s^2 / (196.1 / 65536)
  const std::vector<uint8_t> p = EncodeCristaHighSpeed(s, 0x01020304u, 7, 200);
  ASSERT_EQ(p.size(), kCristaHighSpeedPacket);
  const std::vector<uint8_t> head = {0x55, 0xAA, 0xFF, 18,   0x00, 0x01, 0xFF, 0xFE, 0x12, 0x34, 0x80,
                                     0x00, 0x7F, 0xFF, 0x0C, 0xCE, 0x01, 0x02, 0x03, 0x04, 7,    200};
  EXPECT_EQ(std::vector<uint8_t>(p.begin(), p.begin() + 22), head);
  const uint16_t crc = Crc16Arc(p.data(), 22);
  EXPECT_EQ(p[22], crc >> 8);
  EXPECT_EQ(p[23], crc & 0xFF);
  // A corrupted byte changes the CRC.
  std::vector<uint8_t> bad = p;
  bad[5] ^= 0x10;
  EXPECT_NE(Crc16Arc(bad.data(), 22), crc);
}

TEST(Crista, PacketsArriveUnchangedOnThePseudoTerminal) {
  CristaPty pty;
  const int fd = open(pty.slave_path().c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(fd, 0) << pty.slave_path();
  std::vector<uint8_t> sent;
  for (int k = 0; k < 20; ++k) {
    ImuSample s;
    s.gyro_raw[0] = static_cast<int16_t>(k * 1000 - 7000);
    s.accel_raw[2] = 3278;
    const auto p = EncodeCristaHighSpeed(s, 10000u * k, 0, static_cast<uint8_t>(k));
    ASSERT_TRUE(pty.Write(p));
    sent.insert(sent.end(), p.begin(), p.end());
  }
  std::vector<uint8_t> got;
  for (int tries = 0; tries < 100 && got.size() < sent.size(); ++tries) {
    pollfd pfd{fd, POLLIN, 0};
    poll(&pfd, 1, 20);
    uint8_t buf[512];
    const ssize_t n = read(fd, buf, sizeof(buf));
    if (n > 0) got.insert(got.end(), buf, buf + n);
  }
  close(fd);
  EXPECT_EQ(got, sent);  // raw mode: no byte translated (0x0D, 0x0A, 0x11 ... pass through)
}

}  // namespace rig_sim

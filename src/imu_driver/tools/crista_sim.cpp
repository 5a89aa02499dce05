// crista_sim: a simulated Crista IMU on a pseudo-terminal, for demos and for
// running the driver without hardware. The IMU turns at a constant rate, so
// gravity turns in its frame; the gyro has a bias and both sensors white noise.
//
//   crista_sim --link /tmp/crista --rate 100 --seconds 0 --omega 0,0,0.2
//              --gyro-bias 0.01,-0.005,0.002 --gyro-sigma 0.003 --accel-sigma 0.03 --garbage 0.0
//
// Then: rosrun imu_driver imu_driver_node _port:=/tmp/crista
#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "imu_driver/core/crista_protocol.h"
#include "imu_driver/core/pseudo_terminal.h"

namespace {

// SIGINT/SIGTERM (roslaunch shutdown) end the loop so the pty's link is removed:
// a stale link would later point at whatever pty reuses the number.
std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

// A whole number, or throws naming the option.
double ParseNumber(const std::string& option, const std::string& s) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !std::isfinite(v))
    throw std::invalid_argument(option + " needs a number, got '" + s + "'");
  return v;
}

Eigen::Vector3d ParseVector(const std::string& option, const std::string& s) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  std::stringstream ss(s);
  std::string item;
  int i = 0;
  for (; i < 3 && std::getline(ss, item, ','); ++i) v(i) = ParseNumber(option, item);
  if (i != 3 || std::getline(ss, item)) throw std::invalid_argument(option + " needs x,y,z, got '" + s + "'");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> a = {
      {"--link", "/tmp/crista"}, {"--rate", "100"},        {"--seconds", "0"},
      {"--omega", "0,0,0"},      {"--gyro-bias", "0,0,0"}, {"--gyro-sigma", "0.003"},
      {"--accel-sigma", "0.03"}, {"--garbage", "0"},       {"--seed", "1"}};
  for (int i = 1; i < argc; i += 2) {
    if (std::string(argv[i]).find(":=") != std::string::npos) {  // roslaunch's __name:=, __log:=
      --i;
      continue;
    }
    if (!a.count(argv[i])) {
      std::fprintf(stderr, "crista_sim: unknown option %s\n", argv[i]);
      return 2;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "crista_sim: %s needs a value\n", argv[i]);
      return 2;
    }
    a[argv[i]] = argv[i + 1];
  }
  double rate_hz = 0.0, seconds = 0.0, gyro_sigma = 0.0, accel_sigma = 0.0, garbage = 0.0, seed = 0.0;
  Eigen::Vector3d omega, bias;
  try {
    rate_hz = ParseNumber("--rate", a["--rate"]);
    seconds = ParseNumber("--seconds", a["--seconds"]);
    omega = ParseVector("--omega", a["--omega"]);
    bias = ParseVector("--gyro-bias", a["--gyro-bias"]);
    gyro_sigma = ParseNumber("--gyro-sigma", a["--gyro-sigma"]);
    accel_sigma = ParseNumber("--accel-sigma", a["--accel-sigma"]);
    garbage = ParseNumber("--garbage", a["--garbage"]);
    seed = ParseNumber("--seed", a["--seed"]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "crista_sim: %s\n", e.what());
    return 2;
  }
  if (!(rate_hz > 0.0)) {
    std::fprintf(stderr, "crista_sim: --rate must be positive\n");
    return 2;
  }
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  imu_driver::PseudoTerminal pty(a["--link"]);
  try {
    pty.Plug();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "crista_sim: %s\n", e.what());
    return 1;
  }
  std::printf("crista_sim: %s -> %s at %g Hz\n", pty.link().c_str(), pty.slave_name().c_str(), rate_hz);
  std::fflush(stdout);

  Eigen::Quaterniond q_world_imu = Eigen::Quaterniond::Identity();
  const auto start = std::chrono::steady_clock::now();
  for (uint64_t k = 0; !g_stop && (seconds <= 0.0 || k < seconds * rate_hz); ++k) {
    const double dt = 1.0 / rate_hz;
    const Eigen::Vector3d up_world(0.0, 0.0, 9.81);  // what an accelerometer at rest reads
    imu_driver::ImuSampleSi si;
    const Eigen::Vector3d w = omega + bias + gyro_sigma * Eigen::Vector3d(n(rng), n(rng), n(rng));
    const Eigen::Vector3d f =
        q_world_imu.conjugate() * up_world + accel_sigma * Eigen::Vector3d(n(rng), n(rng), n(rng));
    for (int i = 0; i < 3; ++i) {
      si.omega_imu_rad_s[i] = w(i);
      si.accel_imu_m_s2[i] = f(i);
    }
    si.time_since_pps_s = k * dt;
    si.sequence = static_cast<uint8_t>(k);
    std::vector<uint8_t> bytes = imu_driver::EncodeHighSpeedFrame(imu_driver::FromSi(si));
    if (u(rng) < garbage) bytes.insert(bytes.begin(), static_cast<uint8_t>(rng()));
    try {
      pty.WriteIfRoom(bytes.data(), bytes.size());  // nobody reading: the sample is lost, as on the wire
    } catch (const std::exception& e) {
      std::fprintf(stderr, "crista_sim: %s\n", e.what());
      return 1;
    }
    if (omega.norm() > 0.0) {
      q_world_imu =
          (q_world_imu * Eigen::Quaterniond(Eigen::AngleAxisd(omega.norm() * dt, omega.normalized()))).normalized();
    }
    std::this_thread::sleep_until(start + std::chrono::duration<double>((k + 1) * dt));
  }
  return 0;
}

// Runs arv-fake-gv-camera-0.8 (a GigE Vision camera simulator on loopback) as a
// child process for the driver tests.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace aravis_camera {
namespace test {

// Only one fake camera can hold the loopback GVCP port; every test that starts
// one takes this lock first (the rostest through `flock` on the same file).
constexpr const char* kFakeCameraLock = "/tmp/aravis_camera_fake_gv.lock";
constexpr const char* kFakeCameraAddress = "127.0.0.1";

inline int LockFakeCameraPort() {
  const int fd = open(kFakeCameraLock, O_CREAT | O_RDWR, 0666);
  if (fd >= 0) flock(fd, LOCK_EX);
  return fd;
}

class FakeCamera {
 public:
  explicit FakeCamera(int lost_packets_per_thousand = 0) : lost_(lost_packets_per_thousand) { Start(); }
  ~FakeCamera() { Kill(); }

  void Start() {
    pid_ = fork();
    if (pid_ == 0) {
      const int devnull = open("/dev/null", O_WRONLY);
      dup2(devnull, STDOUT_FILENO);
      dup2(devnull, STDERR_FILENO);
      const std::string lost = std::to_string(lost_);
      execlp("arv-fake-gv-camera-0.8", "arv-fake-gv-camera-0.8", "-i", kFakeCameraAddress, "-s", "GVTEST", "-r",
             lost.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }

  // SIGKILL: the camera vanishes mid-stream, as when its cable is pulled.
  void Kill() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
  }

 private:
  int lost_;
  pid_t pid_ = -1;
};

}  // namespace test
}  // namespace aravis_camera

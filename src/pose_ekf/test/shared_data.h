// The project's real data beside the repository (../shared/data, also from a worktree one level deeper), for the
// tests that read it and skip when it is absent.
#pragma once

#include <cstdlib>
#include <fstream>
#include <string>

namespace pose_ekf_test {

// ../shared/data/<subdir> found from the package source, or the folder the environment variable env names; ""
// when neither holds probe_file.
inline std::string SharedDataDir(const std::string& subdir, const std::string& probe_file, const char* env) {
  if (const char* dir = std::getenv(env)) return dir;
  const std::string pkg = POSE_EKF_SOURCE_DIR;
  for (const char* up : {"/../..", "/../../.."})
    for (const char* shared : {"/../shared", "/../../shared"}) {
      const std::string dir = pkg + up + shared + "/data/" + subdir;
      if (std::ifstream(dir + "/" + probe_file)) return dir;
    }
  return "";
}

}  // namespace pose_ekf_test

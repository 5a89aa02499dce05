// Helpers the rig_model tests share.
#pragma once

#include <unistd.h>

#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "rig_model/strict_yaml.h"

namespace rig_model {

// what() of the FileError that f throws, or "" when it throws none.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const FileError& e) {
    return e.what();
  }
  return "";
}

// Writes `text` (bytes as given) to a file called `name` in a directory of this test process's own.
inline std::string WriteTestFile(const std::string& name, const std::string& text) {
  const std::string dir = testing::TempDir() + "rig_model_test_" + std::to_string(getpid());
  (void)system(("mkdir -p '" + dir + "'").c_str());
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace rig_model

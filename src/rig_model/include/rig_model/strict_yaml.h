// Strict reading of the project's YAML files: every file the project reads refuses unknown or
// misspelt keys, naming the file, the key, the line and the nearest known key. ROS-free.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace rig_model {

// A problem with an input file's content; what() names the file, line and field.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The candidate closest to `key` by edit distance, or "" when none is close enough to be a typo
// (more than a third of the key's letters, at least 2, would have to change).
std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates);

// Loads a YAML file. Throws FileError naming the file when it cannot be read, is not valid
// UTF-8 text, or does not parse (with the parser's line).
YAML::Node LoadYamlFile(const std::string& path);

// Reads YAML mappings of one file, refusing what a user did not mean.
class StrictReader {
 public:
  explicit StrictReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  // Throws FileError unless `node` is a mapping whose keys are all in `known`:
  // "cones.yaml:7: unknown key 'cones[0].hieght_m' (did you mean 'height_m'?)".
  // `where` is the mapping's path in the file ("" for the top level).
  void CheckKeys(const YAML::Node& node, const std::vector<std::string>& known, const std::string& where) const;

  // A finite number at `where.key`, or `fallback` when the key is absent.
  double Number(const YAML::Node& map, const std::string& where, const std::string& key, double fallback) const;
  // A required finite number.
  double RequiredNumber(const YAML::Node& map, const std::string& where, const std::string& key) const;
  // A string at `where.key`, or `fallback` when absent.
  std::string String(const YAML::Node& map, const std::string& where, const std::string& key,
                     const std::string& fallback) const;

  // "file:line: where.key: what", for the caller's own checks.
  [[noreturn]] void Fail(const YAML::Node& at, const std::string& field, const std::string& what) const;

 private:
  std::string file_;
};

// "where.key", or "key" at the top level.
std::string FieldPath(const std::string& where, const std::string& key);

}  // namespace rig_model

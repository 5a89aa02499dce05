#include "rig_model/strict_yaml.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace rig_model {
namespace {

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// RFC 3629 well-formedness; yaml-cpp would otherwise report a codec error without the file's name.
bool IsUtf8(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int extra = c < 0x80 ? 0 : (c >> 5) == 0x6 ? 1 : (c >> 4) == 0xE ? 2 : (c >> 3) == 0x1E ? 3 : -1;
    if (extra < 0 || (extra == 1 && c < 0xC2) || i + extra >= s.size()) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    }
    i += extra + 1;
  }
  return true;
}

std::string Line(const YAML::Node& n) { return n.Mark().line >= 0 ? std::to_string(n.Mark().line + 1) : "?"; }

}  // namespace

std::string FieldPath(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, key.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const size_t d = EditDistance(key, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

YAML::Node LoadYamlFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path + ": cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  if (!IsUtf8(text.str())) throw FileError(path + ": not a text file (invalid UTF-8); expected YAML");
  try {
    return YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw FileError(path + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
}

void StrictReader::Fail(const YAML::Node& at, const std::string& field, const std::string& what) const {
  throw FileError(file_ + ":" + Line(at) + ": " + field + ": " + what);
}

void StrictReader::CheckKeys(const YAML::Node& node, const std::vector<std::string>& known,
                             const std::string& where) const {
  if (!node.IsMap()) Fail(node, where.empty() ? "the file" : where, "must be a mapping of key: value");
  std::map<std::string, std::string> seen;  // key -> its line: yaml-cpp's map[key] would take the first silently
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    if (!seen.emplace(key, Line(entry.first)).second) {
      throw FileError(file_ + ":" + Line(entry.first) + ": duplicate key '" + FieldPath(where, key) +
                      "' (first at line " + seen[key] + ")");
    }
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    const std::string nearest = NearestKey(key, known);
    std::string message = file_ + ":" + Line(entry.first) + ": unknown key '" + FieldPath(where, key) + "'";
    if (!nearest.empty()) {
      message += " (did you mean '" + nearest + "'?)";
    } else {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      message += "; known keys: " + list;
    }
    throw FileError(message);
  }
}

double StrictReader::Number(const YAML::Node& map, const std::string& where, const std::string& key,
                            double fallback) const {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    Fail(n, FieldPath(where, key), "must be a number");
  }
  if (!std::isfinite(v)) Fail(n, FieldPath(where, key), "must be finite");
  return v;
}

double StrictReader::RequiredNumber(const YAML::Node& map, const std::string& where, const std::string& key) const {
  if (!map[key]) Fail(map, FieldPath(where, key), "is missing");
  return Number(map, where, key, 0.0);
}

std::string StrictReader::String(const YAML::Node& map, const std::string& where, const std::string& key,
                                 const std::string& fallback) const {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  if (!n.IsScalar()) Fail(n, FieldPath(where, key), "must be a string");
  return n.Scalar();
}

}  // namespace rig_model

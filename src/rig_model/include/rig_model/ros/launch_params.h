// For tests that every parameter a shipped launch file gives a node loads through the node's
// parameter table: the <param>s inside the <node>s whose attributes mention `node` (e.g.
// "ar_overlay/OverlayNodelet"), with $(arg x) replaced by x's default in the same file.
// Header-only and deliberately small: one <param name=... value=.../> per tag, no includes.
#pragma once

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <ros/node_handle.h>

namespace rig_model {

struct LaunchParam {
  std::string name;
  std::string
      value;  // "" with resolved == false when it needs something a test cannot know ($(find), an arg without default)
  std::string type;  // the tag's type attribute, "" when roslaunch guesses it from the value
  bool resolved = false;
};

inline std::string LaunchAttribute(const std::string& tag, const std::string& attribute) {
  const std::regex re("\\b" + attribute + "\\s*=\\s*\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(tag, m, re) ? m[1].str() : std::string();
}

inline std::vector<LaunchParam> LaunchParams(const std::string& path, const std::string& node) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = std::regex_replace(ss.str(), std::regex("<!--[\\s\\S]*?-->"), "");
  std::map<std::string, std::string> defaults;
  const std::regex arg_re("<arg\\s[^>]*>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), arg_re); it != std::sregex_iterator(); ++it) {
    const std::string tag = it->str();
    if (tag.find("default=") != std::string::npos)
      defaults[LaunchAttribute(tag, "name")] = LaunchAttribute(tag, "default");
  }
  std::vector<LaunchParam> params;
  const std::regex node_re("<node\\s([^>]*[^/])>([\\s\\S]*?)</node>");
  const std::regex param_re("<param\\s[^>]*>");
  for (auto n = std::sregex_iterator(text.begin(), text.end(), node_re); n != std::sregex_iterator(); ++n) {
    if ((*n)[1].str().find(node) == std::string::npos) continue;
    const std::string body = (*n)[2].str();
    for (auto p = std::sregex_iterator(body.begin(), body.end(), param_re); p != std::sregex_iterator(); ++p) {
      LaunchParam lp{LaunchAttribute(p->str(), "name"), LaunchAttribute(p->str(), "value"),
                     LaunchAttribute(p->str(), "type")};
      std::smatch m;
      while (std::regex_search(lp.value, m, std::regex("\\$\\(arg ([^)]*)\\)")) && defaults.count(m[1].str()))
        lp.value = m.prefix().str() + defaults[m[1].str()] + m.suffix().str();
      lp.resolved = lp.value.find("$(") == std::string::npos;
      if (!lp.resolved) lp.value.clear();
      params.push_back(lp);
    }
  }
  return params;
}

// Sets the resolved parameters under nh as roslaunch would type them (int, double, bool, string).
inline void SetLaunchParams(const ros::NodeHandle& nh, const std::vector<LaunchParam>& params) {
  for (const LaunchParam& p : params) {
    if (!p.resolved) continue;
    const std::string& v = p.value;
    char* end = nullptr;
    if (p.type == "str") {
      nh.setParam(p.name, v);
    } else if (v == "true" || v == "True" || v == "false" || v == "False") {
      nh.setParam(p.name, v == "true" || v == "True");
    } else if (const long i = std::strtol(v.c_str(), &end, 10); !v.empty() && *end == '\0') {
      nh.setParam(p.name, static_cast<int>(i));
    } else if (const double d = std::strtod(v.c_str(), &end); !v.empty() && *end == '\0') {
      nh.setParam(p.name, d);
    } else {
      nh.setParam(p.name, v);
    }
  }
}

}  // namespace rig_model

// pnp_solve: run the pose library on JSONL cases.
//   pnp_solve --method NAME --input cases.jsonl --output poses.jsonl
// Input line:  {"K":[fx,fy,cx,cy], "dist":[k1,k2,p1,p2], "model":[[X,Y,Z],…],
//               "image":[[u,v],…], "sigma_px":s}   (optional "init":{"q":[w,x,y,z],"t":[x,y,z]})
// Output line: {"ok":bool, "q":[w,x,y,z], "t":[x,y,z], "cov6":[36, rotation vector then
//               translation], "iterations":n, "reproj_rms_px":e, "time_us":µs} (+ "error" when !ok)
// --ransac-px T: matches with outliers (ransac.h); the output adds "inliers":n and "outliers":[indices].
// Exit status 1 when any case failed (one stderr line each, with its line number), 2 for bad arguments.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cone_tracker/pose/pnp.h"
#include "pnp_json.h"

namespace {

using nlohmann::json;

void Usage(std::ostream& out) {
  out << "usage: pnp_solve [--method NAME] [--ransac-px T] --input cases.jsonl --output poses.jsonl\n"
         "  Solves each JSON line {\"K\":[fx,fy,cx,cy], \"dist\":[k1,k2,p1,p2], \"model\":[[X,Y,Z],...],\n"
         "  \"image\":[[u,v],...], \"sigma_px\":s} for the model in the camera (p_c = R p_m + t).\n"
         "  Use \"-\" for stdin/stdout.\nmethods:";
  for (const std::string& name : cone_tracker::PnpMethodNames()) out << ' ' << name;
  out << "\n  default: best (linear initialisation + refinement, what the tracker uses)\n"
         "  --ransac-px T: the matches may hold outliers: RANSAC (P3P samples) keeps those within T px, the\n"
         "  method solves on them, and each output line adds \"inliers\":n and \"outliers\":[indices]\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string method = "best", input, output;
  std::optional<cone_tracker::RansacOptions> ransac;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      Usage(std::cout);
      return 0;
    }
    if (a == "--ransac-px" && i + 1 < argc) {
      const std::string v = argv[++i];
      char* end = nullptr;
      const double t = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(t > 0.0) || !std::isfinite(t)) {
        std::cerr << "pnp_solve: --ransac-px '" << v << "' is not a positive number of pixels\n";
        return 2;
      }
      ransac = cone_tracker::RansacOptions();
      ransac->threshold_px = t;
    } else if ((a == "--method" || a == "--input" || a == "--output") && i + 1 < argc) {
      (a == "--method" ? method : a == "--input" ? input : output) = argv[++i];
    } else {
      std::cerr << "pnp_solve: unknown or incomplete argument '" << a << "'\n";
      Usage(std::cerr);
      return 2;
    }
  }
  const auto m = cone_tracker::PnpMethodFromName(method);
  if (!m || input.empty() || output.empty()) {
    if (!m) std::cerr << "pnp_solve: unknown method '" << method << "'\n";
    Usage(std::cerr);
    return 2;
  }
  cone_tracker::PnpOptions options;
  options.method = *m;
  std::ifstream in_file;
  std::ofstream out_file;
  if (input != "-") in_file.open(input);
  if (output != "-") out_file.open(output);
  std::istream& in = input == "-" ? std::cin : in_file;
  std::ostream& out = output == "-" ? std::cout : out_file;
  if (!in || !out) {
    std::cerr << "pnp_solve: cannot open " << (!in ? input : output) << "\n";
    return 1;
  }
  std::string line;
  int line_number = 0, failures = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    nlohmann::ordered_json result;
    try {
      result = cone_tracker::SolveJsonCase(json::parse(line), options, ransac ? &*ransac : nullptr);
    } catch (const std::exception& e) {  // not JSON at all
      result["ok"] = false;
      result["error"] = e.what();
    }
    if (!result["ok"].get<bool>()) {
      result["error"] = "line " + std::to_string(line_number) + ": " + result["error"].get<std::string>();
      std::cerr << "pnp_solve: " << (input == "-" ? "stdin" : input) << ": " << result["error"].get<std::string>()
                << "\n";
      ++failures;
    }
    out << result.dump() << "\n";
  }
  if (in.bad()) {
    std::cerr << "pnp_solve: reading " << input << " failed after line " << line_number << "\n";
    return 1;
  }
  out.flush();
  if (!out) {
    std::cerr << "pnp_solve: writing " << output << " failed\n";
    return 1;
  }
  if (failures > 0) std::cerr << "pnp_solve: " << failures << " of " << line_number << " line(s) failed\n";
  return failures > 0 ? 1 : 0;
}

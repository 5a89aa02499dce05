// pnp_solve: run the pose library on JSONL cases.
//   pnp_solve --method NAME --input cases.jsonl --output poses.jsonl
// Input line:  {"K":[fx,fy,cx,cy], "dist":[k1,k2,p1,p2], "model":[[X,Y,Z],…],
//               "image":[[u,v],…], "sigma_px":s}   (optional "init":{"q":[w,x,y,z],"t":[x,y,z]})
// Output line: {"ok":bool, "q":[w,x,y,z], "t":[x,y,z], "cov6":[36, rotation vector then
//               translation], "iterations":n, "reproj_rms_px":e, "time_us":µs} (+ "error" when !ok)
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cone_tracker/pose/pnp.h"

namespace {

using nlohmann::json;

void Usage(std::ostream& out) {
  out << "usage: pnp_solve [--method NAME] --input cases.jsonl --output poses.jsonl\n"
         "  Solves each JSON line {\"K\":[fx,fy,cx,cy], \"dist\":[k1,k2,p1,p2], \"model\":[[X,Y,Z],...],\n"
         "  \"image\":[[u,v],...], \"sigma_px\":s} for the model in the camera (p_c = R p_m + t).\n"
         "  Use \"-\" for stdin/stdout.\nmethods:";
  for (const std::string& name : cone_tracker::PnpMethodNames()) out << ' ' << name;
  out << "\n  default: best (linear initialisation + refinement, what the tracker uses)\n";
}

json Solve(const json& in, cone_tracker::PnpOptions options) {
  cone_tracker::CameraModel camera;
  const auto K = in.at("K").get<std::vector<double>>();
  if (K.size() != 4) throw std::invalid_argument("K must be [fx, fy, cx, cy]");
  camera.fx_px = K[0], camera.fy_px = K[1], camera.cx_px = K[2], camera.cy_px = K[3];
  if (in.contains("dist")) camera.distortion = in.at("dist").get<std::vector<double>>();
  std::vector<Eigen::Vector3d> model;
  for (const auto& p : in.at("model")) {
    const auto v = p.get<std::vector<double>>();
    if (v.size() != 3) throw std::invalid_argument("model points must be [X, Y, Z]");
    model.emplace_back(v[0], v[1], v[2]);
  }
  std::vector<Eigen::Vector2d> image;
  for (const auto& p : in.at("image")) {
    const auto v = p.get<std::vector<double>>();
    if (v.size() != 2) throw std::invalid_argument("image points must be [u, v]");
    image.emplace_back(v[0], v[1]);
  }
  if (in.contains("sigma_px")) options.sigma_px = in.at("sigma_px").get<double>();
  std::optional<pose_math::Pose> init;
  if (in.contains("init")) {
    const auto q = in.at("init").at("q").get<std::vector<double>>();
    const auto t = in.at("init").at("t").get<std::vector<double>>();
    if (q.size() != 4 || t.size() != 3) throw std::invalid_argument("init needs q[4] and t[3]");
    init = pose_math::Pose{pose_math::Quat(q[0], q[1], q[2], q[3]).normalized(), Eigen::Vector3d(t[0], t[1], t[2])};
  }
  const auto start = std::chrono::steady_clock::now();
  const cone_tracker::PnpResult r = cone_tracker::SolvePnp(camera, model, image, options, init);
  const double time_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  json out;
  out["ok"] = r.ok;
  if (!r.ok) {
    out["error"] = r.error;
    out["time_us"] = time_us;
    return out;
  }
  const pose_math::Quat& q = r.T_camera_model.q;
  out["q"] = {q[0], q[1], q[2], q[3]};
  out["t"] = {r.T_camera_model.t.x(), r.T_camera_model.t.y(), r.T_camera_model.t.z()};
  // ROS order is (x y z rx ry rz); the tool's is rotation vector then translation.
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
  P.topRightCorner<3, 3>().setIdentity();
  P.bottomLeftCorner<3, 3>().setIdentity();
  const Eigen::Matrix<double, 6, 6> cov = P * r.cov6_ros * P.transpose();
  std::vector<double> cov6;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) cov6.push_back(cov(i, j));
  out["cov6"] = cov6;
  out["iterations"] = r.iterations;
  out["reproj_rms_px"] = r.reproj_rms_px;
  out["time_us"] = time_us;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string method = "best", input, output;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      Usage(std::cout);
      return 0;
    }
    if ((a == "--method" || a == "--input" || a == "--output") && i + 1 < argc) {
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
    json result;
    try {
      result = Solve(json::parse(line), options);
    } catch (const std::exception& e) {
      result = {{"ok", false}, {"error", "line " + std::to_string(line_number) + ": " + e.what()}};
    }
    failures += result["ok"].get<bool>() ? 0 : 1;
    out << result.dump() << "\n";
  }
  if (failures > 0) std::cerr << "pnp_solve: " << failures << " case(s) failed, see \"error\" in the output\n";
  return 0;
}

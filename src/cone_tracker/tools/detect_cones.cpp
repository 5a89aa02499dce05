// detect_cones --config FILE|photos [--layout FILE] --output out.jsonl IMAGE...
// Runs the segmentation on image files and writes one JSON line per image:
// {"image":path, "cones":[{"bbox":[x,y,w,h], "peak":[u,v], "mid":[u,v],
// "base":[u,v], "area":a, "solidity":s, "score":p, "points":"colour"|"box"}, ...],
// "rejected":[{"bbox":[x,y,w,h], "area":a, "gates":["outline", ...]}, ...], "ms":t}
// (or "error"). score: the learned detector's (detector: dnn), 1 for colour
// detections; points: where peak/mid/base came from (vision/cone_detector.h);
// ms: the detection's wall time. For tuning the thresholds on one's own photos;
// no camera calibration (no undistortion). --layout: the layout's collars, for reading cones cut by the image's edge
// (vision/collar_ruler.h; "by_collars": true on such a cone). Prints the median and mean time at the end.
// Exit status 1 when any image could not be read or segmented (one stderr line
// each, naming the file), 2 for bad arguments or config.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cone_tracker/node/params.h"
#include "cone_tracker/vision/cone_detector.h"
#include "cone_tracker/vision/cone_pose.h"
#include "rig_model/strict_yaml.h"

namespace {

nlohmann::json Uv(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

}  // namespace

int main(int argc, char** argv) {
  std::string config_path, layout_path, output;
  std::vector<std::string> images;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--config" && i + 1 < argc)
      config_path = argv[++i];
    else if (a == "--layout" && i + 1 < argc)
      layout_path = argv[++i];
    else if (a == "--output" && i + 1 < argc)
      output = argv[++i];
    else
      images.push_back(a);
  }
  if (output.empty() || images.empty()) {
    std::fprintf(stderr, "usage: detect_cones [--config FILE|photos] [--layout FILE] --output out.jsonl IMAGE...\n");
    return 2;
  }
  if (config_path == "photos") config_path = std::string(CONE_TRACKER_CONFIG_DIR) + "/photos.yaml";
  // Our own line per unreadable image names it and says why; OpenCV's warning would be a second one.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  std::unique_ptr<cone_tracker::ConeDetector> seg;  // built once: the colour table takes ~0.1 s
  try {
    cone_tracker::NodeConfig c =
        config_path.empty() ? cone_tracker::NodeConfig() : cone_tracker::LoadConfigFile(config_path);
    if (!layout_path.empty())
      c.segmenter.collar.collars =
          cone_tracker::CommonCollars(cone_tracker::ConeModels(rig_model::LoadLayoutFile(layout_path)));
    seg = std::make_unique<cone_tracker::ConeDetector>(c.segmenter, c.detector);
  } catch (const rig_model::FileError& e) {  // names the file, line and key
    std::fprintf(stderr, "detect_cones: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detect_cones: config %s: %s\n", config_path.c_str(), e.what());
    return 2;
  }
  std::ofstream out(output);
  if (!out) {
    std::fprintf(stderr, "detect_cones: cannot write %s\n", output.c_str());
    return 1;
  }
  int found = 0, failed = 0;
  std::vector<double> times_ms;
  for (const std::string& path : images) {
    nlohmann::json line = {{"image", path}};
    const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
    if (bgr.empty()) {
      const bool opens = bool(std::ifstream(path, std::ios::binary));
      const std::string why = opens ? "not an image OpenCV can decode" : std::strerror(errno);
      line["error"] = "cannot read the image: " + why;
      std::fprintf(stderr, "detect_cones: %s: cannot read the image: %s\n", path.c_str(), why.c_str());
      ++failed;
    } else {
      const auto t0 = std::chrono::steady_clock::now();
      const cone_tracker::ConeDetectorResult dr =
          seg->Process({bgr.data, bgr.cols, bgr.rows, int(bgr.step), "bgr8"}, cone_tracker::CameraModel());
      times_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      const cone_tracker::SegmentationResult& r = dr.segmentation;
      line["cones"] = nlohmann::json::array();
      if (!r.ok) {
        line["error"] = r.error;
        std::fprintf(stderr, "detect_cones: %s: %s\n", path.c_str(), r.error.c_str());
        ++failed;
      }
      for (size_t i = 0; i < r.cones.size(); ++i) {
        const auto& d = r.cones[i];
        const auto& b = d.blob;
        line["cones"].push_back({{"bbox", {b.bbox_x, b.bbox_y, b.bbox_w, b.bbox_h}},
                                 {"peak", Uv(d.peak_px)},
                                 {"mid", Uv(d.mid_px)},
                                 {"base", Uv(d.base_px)},
                                 {"area", b.area},
                                 {"solidity", b.solidity},
                                 {"score", dr.scores[i]},
                                 {"points", dr.points_from_colour[i] ? "colour" : "box"}});
        if (d.by_collars) line["cones"].back()["by_collars"] = true;
      }
      line["rejected"] = nlohmann::json::array();
      for (const auto& d : r.rejected) {
        const auto& b = d.blob;
        line["rejected"].push_back({{"bbox", {b.bbox_x, b.bbox_y, b.bbox_w, b.bbox_h}},
                                    {"area", b.area},
                                    {"gates", cone_tracker::SegmentationGateNames(d.failed_gates)}});
      }
      line["ms"] = times_ms.back();
      found += int(r.cones.size());
    }
    out << line.dump() << "\n";
  }
  out.flush();
  if (!out) {
    std::fprintf(stderr, "detect_cones: writing %s failed\n", output.c_str());
    return 1;
  }
  std::printf("detect_cones: %zu images, %d cones, %d failed\n", images.size(), found, failed);
  if (!times_ms.empty()) {
    double sum = 0;
    for (double t : times_ms) sum += t;
    std::nth_element(times_ms.begin(), times_ms.begin() + times_ms.size() / 2, times_ms.end());
    std::printf("detect_cones: %.1f ms per image (median), %.1f ms (mean)\n", times_ms[times_ms.size() / 2],
                sum / times_ms.size());
  }
  return failed > 0 ? 1 : 0;
}

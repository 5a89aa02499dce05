#include "cone_tracker/node/visuals.h"

#include <cmath>
#include <cstdio>

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgproc.hpp>

namespace cone_tracker {
namespace {

const cv::Scalar kGreen(60, 220, 60), kRed(40, 40, 230), kCyan(230, 220, 40), kYellow(40, 230, 240),
    kWhite(255, 255, 255);

cv::Point Px(const Eigen::Vector2d& p) { return cv::Point(int(std::lround(p.x())), int(std::lround(p.y()))); }

void Text(cv::Mat* img, const std::string& s, cv::Point at, const cv::Scalar& color, double scale) {
  cv::putText(*img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(*img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, color, 1, cv::LINE_AA);
}

void TintMask(cv::Mat* img, const std::vector<uint8_t>& mask) {
  if (mask.size() != size_t(img->rows) * size_t(img->cols)) return;
  for (int y = 0; y < img->rows; ++y) {
    cv::Vec3b* row = img->ptr<cv::Vec3b>(y);
    const uint8_t* m = mask.data() + size_t(y) * img->cols;
    for (int x = 0; x < img->cols; ++x)
      if (m[x]) row[x] = cv::Vec3b(uint8_t(row[x][0] / 4), uint8_t(row[x][1] / 4 + 191), uint8_t(row[x][2] / 4));
  }
}

void DrawDetection(cv::Mat* img, const ConeDetection& d, int cone_id, const DebugImageConfig& cfg, double scale) {
  const Blob& b = d.blob;
  const cv::Scalar box = d.accepted() ? kGreen : kRed;
  cv::rectangle(*img, cv::Rect(b.bbox_x, b.bbox_y, b.bbox_w, b.bbox_h), box, 1);
  if (!d.accepted()) {
    if (cfg.draw_text) {
      std::string gates;
      for (const std::string& g : SegmentationGateNames(d.failed_gates)) gates += (gates.empty() ? "" : ",") + g;
      Text(img, gates, cv::Point(b.bbox_x, b.bbox_y + b.bbox_h + int(14 * scale)), kRed, 0.4 * scale);
    }
    return;
  }
  cv::line(*img, Px(d.peak_px), Px(d.base_px), kCyan, 1, cv::LINE_AA);
  cv::drawMarker(*img, Px(d.peak_px), kYellow, cv::MARKER_TRIANGLE_UP, int(10 * scale), 1);
  cv::drawMarker(*img, Px(d.mid_px), kCyan, cv::MARKER_CROSS, int(8 * scale), 1);
  cv::drawMarker(*img, Px(d.base_px), kYellow, cv::MARKER_SQUARE, int(8 * scale), 1);
  if (cfg.draw_text) {
    const std::string id = cone_id >= 0 ? "cone " + std::to_string(cone_id) : "cone ?";
    Text(img, id, cv::Point(b.bbox_x, std::max(int(12 * scale), b.bbox_y - 4)), kGreen, 0.45 * scale);
  }
}

}  // namespace

sensor_msgs::ImagePtr MakeDebugImage(const sensor_msgs::ImageConstPtr& image, const std::vector<uint8_t>& mask,
                                     const FrameResult& r, const DebugImageConfig& cfg) {
  cv_bridge::CvImagePtr cv;
  try {
    cv = cv_bridge::toCvCopy(image, "bgr8");  // only while someone watches, so the copy is fine
  } catch (const std::exception&) {
    return nullptr;
  }
  cv::Mat& img = cv->image;
  if (img.empty()) return nullptr;
  const double scale = std::max(0.6, img.cols / 1024.0 * 1.6);
  if (cfg.tint_mask) TintMask(&img, mask);
  const SegmentationResult& seg = r.segmentation;
  if (seg.roi_w > 0 && seg.roi_h > 0)
    cv::rectangle(img, cv::Rect(seg.roi_x, seg.roi_y, seg.roi_w, seg.roi_h), kWhite, 1);
  for (size_t i = 0; i < seg.cones.size(); ++i) {
    const auto& a = r.cone_pose.cone_of_detection;
    DrawDetection(&img, seg.cones[i], i < a.size() ? a[i] : -1, cfg, scale);
  }
  if (cfg.draw_rejected)
    for (const ConeDetection& d : seg.rejected) DrawDetection(&img, d, -1, cfg, scale);
  if (cfg.draw_text) {
    char line[160];
    if (r.status == FrameStatus::kPose) {
      std::snprintf(line, sizeof line, "pose: %zu cones, chi2 %.1f < %.1f, rms %.2f px, pred %s", seg.cones.size(),
                    r.cone_pose.chi2, r.cone_pose.chi2_threshold, r.cone_pose.pnp.reproj_rms_px,
                    r.prediction_source.c_str());
      Text(&img, line, cv::Point(4, int(14 * scale)), kGreen, 0.45 * scale);
    } else {
      Text(&img, std::string("no pose: ") + ToString(r.status), cv::Point(4, int(14 * scale)), kRed, 0.45 * scale);
      Text(&img, r.message.substr(0, 90), cv::Point(4, int(30 * scale)), kRed, 0.35 * scale);
    }
  }
  return cv->toImageMsg();
}

visualization_msgs::MarkerArray MakeLayoutMarkers(const std::vector<ConeModel>& layout, const std::string& frame_id) {
  visualization_msgs::MarkerArray out;
  constexpr int kSides = 24;
  for (size_t i = 0; i < layout.size(); ++i) {
    const ConeModel& c = layout[i];
    visualization_msgs::Marker m;
    m.header.frame_id = frame_id;
    m.ns = "cone_tracker/layout";
    m.id = int(i);
    m.type = visualization_msgs::Marker::TRIANGLE_LIST;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 1.0;
    m.color.r = 1.0f, m.color.g = 0.35f, m.color.b = 0.0f, m.color.a = 0.9f;
    const double r = c.tau * c.height_m;
    geometry_msgs::Point apex, centre;
    apex.x = centre.x = c.base_m.x(), apex.y = centre.y = c.base_m.y();
    centre.z = c.base_m.z(), apex.z = c.base_m.z() + c.height_m;
    for (int k = 0; k < kSides; ++k) {
      geometry_msgs::Point a = centre, b = centre;
      a.x += r * std::cos(2 * M_PI * k / kSides), a.y += r * std::sin(2 * M_PI * k / kSides);
      b.x += r * std::cos(2 * M_PI * (k + 1) / kSides), b.y += r * std::sin(2 * M_PI * (k + 1) / kSides);
      m.points.insert(m.points.end(), {apex, a, b, centre, b, a});  // side and base
    }
    out.markers.push_back(m);
    visualization_msgs::Marker t;
    t.header.frame_id = frame_id;
    t.ns = "cone_tracker/ids";
    t.id = int(i);
    t.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    t.action = visualization_msgs::Marker::ADD;
    t.pose.position = apex;
    t.pose.position.z += 0.15;
    t.pose.orientation.w = 1.0;
    t.scale.z = 0.15;
    t.color.r = t.color.g = t.color.b = t.color.a = 1.0f;
    t.text = "cone " + std::to_string(i);
    out.markers.push_back(t);
  }
  return out;
}

}  // namespace cone_tracker

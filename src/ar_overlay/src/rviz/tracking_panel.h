// ar_overlay/TrackingPanel, the thesis's GUI (6.5, 8) as an rviz panel: the
// EKF's sensor switches (camera, gyro, accelerometer updates) and noise, the
// cone colour thresholds, and a live preview of the classified mask. Each
// block is a dynamic_reconfigure client (reconfigure_section.h); the servers'
// namespaces and the preview topic are panel settings saved in the .rviz file.
#pragma once

#include <rviz/panel.h>

class QLineEdit;

namespace ar_overlay {

class MaskView;
class ReconfigureSection;

class TrackingPanel : public rviz::Panel {
  Q_OBJECT
 public:
  explicit TrackingPanel(QWidget* parent = nullptr);
  void onInitialize() override;
  void load(const rviz::Config& config) override;
  void save(rviz::Config config) const override;

 private:
  void Apply();

  QLineEdit* ekf_ns_ = nullptr;
  QLineEdit* tracker_ns_ = nullptr;
  QLineEdit* mask_topic_ = nullptr;
  ReconfigureSection* ekf_switches_ = nullptr;
  ReconfigureSection* ekf_noise_ = nullptr;
  ReconfigureSection* colour_ = nullptr;
  MaskView* mask_ = nullptr;
};

}  // namespace ar_overlay

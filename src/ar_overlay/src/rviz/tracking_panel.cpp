#include "tracking_panel.h"

#include <pluginlib/class_list_macros.hpp>

#include <QFormLayout>
#include <QLineEdit>
#include <QScrollArea>
#include <QVBoxLayout>

#include "mask_view.h"
#include "reconfigure_section.h"

namespace ar_overlay {

TrackingPanel::TrackingPanel(QWidget* parent) : rviz::Panel(parent) {
  ekf_ns_ = new QLineEdit("/pose_ekf");
  tracker_ns_ = new QLineEdit("/cone_tracker");
  mask_topic_ = new QLineEdit("/cone_tracker/debug_image");
  auto* settings = new QFormLayout;
  settings->addRow("EKF server", ekf_ns_);
  settings->addRow("tracker server", tracker_ns_);
  settings->addRow("mask topic", mask_topic_);

  // Group names are those of pose_ekf's PoseEkf.cfg and cone_tracker's ConeTracker.cfg.
  ekf_switches_ = new ReconfigureSection("Sensors (pose_ekf)");
  ekf_switches_->SetGroups({"switches"});
  ekf_noise_ = new ReconfigureSection("EKF noise (pose_ekf)");
  ekf_noise_->SetGroups({"noise"});
  colour_ = new ReconfigureSection("Cone colour (cone_tracker)");
  colour_->SetGroups({"hsi_bounds"});
  mask_ = new MaskView;

  auto* body = new QWidget;
  auto* column = new QVBoxLayout(body);
  column->addLayout(settings);
  // The switches and the colour bounds with their mask first: what a user changes while looking.
  column->addWidget(ekf_switches_);
  column->addWidget(colour_);
  column->addWidget(mask_, 1);
  column->addWidget(ekf_noise_);
  auto* scroll = new QScrollArea;
  scroll->setWidget(body);
  scroll->setWidgetResizable(true);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(scroll);

  for (QLineEdit* edit : {ekf_ns_, tracker_ns_, mask_topic_})
    connect(edit, &QLineEdit::editingFinished, this, [this] {
      Apply();
      Q_EMIT configChanged();
    });
}

void TrackingPanel::onInitialize() { Apply(); }

void TrackingPanel::Apply() {
  const std::string ekf = ekf_ns_->text().trimmed().toStdString();
  ekf_switches_->SetServer(ekf);
  ekf_noise_->SetServer(ekf);
  colour_->SetServer(tracker_ns_->text().trimmed().toStdString());
  mask_->SetTopic(mask_topic_->text().trimmed().toStdString());
}

void TrackingPanel::load(const rviz::Config& config) {
  rviz::Panel::load(config);
  QString value;
  if (config.mapGetString("EKF server", &value)) ekf_ns_->setText(value);
  if (config.mapGetString("Tracker server", &value)) tracker_ns_->setText(value);
  if (config.mapGetString("Mask topic", &value)) mask_topic_->setText(value);
  Apply();
}

void TrackingPanel::save(rviz::Config config) const {
  rviz::Panel::save(config);
  config.mapSetValue("EKF server", ekf_ns_->text());
  config.mapSetValue("Tracker server", tracker_ns_->text());
  config.mapSetValue("Mask topic", mask_topic_->text());
}

}  // namespace ar_overlay

PLUGINLIB_EXPORT_CLASS(ar_overlay::TrackingPanel, rviz::Panel)

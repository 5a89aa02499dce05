// One dynamic_reconfigure server in the tracking panel: a form built from the
// server's parameter_descriptions (checkbox for bools, slider + spin box for
// bounded numbers), kept in step with parameter_updates, and one
// set_parameters call per edit. ROS callbacks arrive on rviz's GUI thread
// (rviz spins the global queue from its update timer), so widgets are touched
// from one thread only.
#pragma once

#include <ros/ros.h>

#include <QWidget>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ar_overlay/rviz/reconfigure_model.h"

class QLabel;
class QVBoxLayout;

namespace ar_overlay {

class ReconfigureSection : public QWidget {
  Q_OBJECT
 public:
  ReconfigureSection(const QString& title, QWidget* parent = nullptr);
  // "" disconnects. Takes effect at once; the form appears with the description.
  void SetServer(const std::string& server_ns);
  const std::string& server() const { return server_; }
  // Only these groups are shown (all when empty), e.g. pose_ekf's "switches".
  void SetGroups(const std::vector<std::string>& groups) { groups_ = groups; }
  // Sends one parameter; false (and a status message) when the call fails.
  bool Send(const ParamSpec& spec, double value);
  bool Send(const ParamSpec& spec, const std::string& value);
  // For tests: how many parameters the form shows.
  int ParameterCount() const { return static_cast<int>(setters_.size()); }

 private:
  void OnDescription(const dynamic_reconfigure::ConfigDescription& description);
  void OnUpdate(const dynamic_reconfigure::Config& config);
  void Clear();
  QWidget* MakeEditor(const ParamSpec& spec);
  bool Call(const dynamic_reconfigure::Config& request, const std::string& name);

  std::string server_;
  std::vector<std::string> groups_;
  ros::NodeHandle nh_;
  ros::Subscriber description_sub_, update_sub_;
  ros::ServiceClient client_;
  QLabel* status_ = nullptr;
  QVBoxLayout* form_ = nullptr;
  QWidget* content_ = nullptr;
  // Per parameter: shows a value from parameter_updates without sending it back.
  std::map<std::string, std::function<void(const dynamic_reconfigure::Config&)>> setters_;
  bool updating_ = false;
};

}  // namespace ar_overlay

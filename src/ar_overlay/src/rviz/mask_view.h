// The live mask preview: the newest image on a topic (cone_tracker/debug_image,
// where the tracker tints the pixels its colour table classifies as cone),
// scaled to the widget. Subscribing is what makes the tracker build the image,
// so the panel subscribes only while it is shown.
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <QImage>
#include <QWidget>
#include <string>

class QLabel;

namespace ar_overlay {

class MaskView : public QWidget {
  Q_OBJECT
 public:
  explicit MaskView(QWidget* parent = nullptr);
  void SetTopic(const std::string& topic);  // "" unsubscribes
  const std::string& topic() const { return topic_; }
  int frames() const { return frames_; }

 protected:
  void showEvent(QShowEvent* event) override;
  void hideEvent(QHideEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;

 private:
  void OnImage(const sensor_msgs::ImageConstPtr& msg);
  void Subscribe();
  void Redraw();

  std::string topic_;
  ros::NodeHandle nh_;
  ros::Subscriber sub_;
  QLabel* picture_ = nullptr;
  QLabel* caption_ = nullptr;
  QImage image_;
  int frames_ = 0;
};

}  // namespace ar_overlay

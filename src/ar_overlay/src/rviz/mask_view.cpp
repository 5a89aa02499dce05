#include "mask_view.h"

#include <cv_bridge/cv_bridge.h>

#include <QLabel>
#include <QPixmap>
#include <QVBoxLayout>
#include <opencv2/imgproc.hpp>

namespace ar_overlay {

MaskView::MaskView(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  caption_ = new QLabel("mask preview: no topic");
  picture_ = new QLabel;
  picture_->setMinimumSize(160, 120);
  picture_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);  // the pixmap never grows the label
  picture_->setAlignment(Qt::AlignCenter);
  picture_->setStyleSheet("background-color: black;");
  layout->addWidget(caption_);
  layout->addWidget(picture_, 1);
}

void MaskView::SetTopic(const std::string& topic) {
  if (topic == topic_) return;
  topic_ = topic;
  sub_.shutdown();
  image_ = QImage();
  picture_->clear();
  Subscribe();
}

void MaskView::Subscribe() {
  if (topic_.empty() || !isVisible()) {
    sub_.shutdown();
    caption_->setText(topic_.empty() ? "mask preview: no topic" : QString::fromStdString(topic_));
    return;
  }
  if (!sub_) sub_ = nh_.subscribe(topic_, 1, &MaskView::OnImage, this);
  caption_->setText(QString::fromStdString("mask preview: waiting for " + topic_));
}

void MaskView::showEvent(QShowEvent*) { Subscribe(); }
void MaskView::hideEvent(QHideEvent*) { sub_.shutdown(); }
void MaskView::resizeEvent(QResizeEvent*) { Redraw(); }

void MaskView::OnImage(const sensor_msgs::ImageConstPtr& msg) {
  cv::Mat rgb;
  try {
    const cv_bridge::CvImageConstPtr in = cv_bridge::toCvShare(msg);
    if (in->encoding == "mono8" || in->encoding == "8UC1") {
      cv::cvtColor(in->image, rgb, cv::COLOR_GRAY2RGB);
    } else {
      rgb = cv_bridge::cvtColor(in, "rgb8")->image;
    }
  } catch (const std::exception& e) {  // cv_bridge's exceptions derive from std::exception
    caption_->setText(QString::fromStdString(topic_ + ": cannot show " + msg->encoding + " (" + e.what() + ")"));
    return;
  }
  // QImage borrows the pixels; copy() makes it own them.
  image_ = QImage(rgb.data, rgb.cols, rgb.rows, static_cast<int>(rgb.step), QImage::Format_RGB888).copy();
  ++frames_;
  caption_->setText(QString::fromStdString(topic_) + QString(" (%1x%2)").arg(rgb.cols).arg(rgb.rows));
  Redraw();
}

void MaskView::Redraw() {
  if (image_.isNull()) return;
  picture_->setPixmap(
      QPixmap::fromImage(image_.scaled(picture_->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation)));
}

}  // namespace ar_overlay

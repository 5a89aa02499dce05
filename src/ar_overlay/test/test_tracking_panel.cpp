// The tracking panel as rviz loads it (pluginlib, rviz::Panel), driving the
// real pose_ekf nodelet's dynamic_reconfigure server (tracking_panel.test), and
// its mask preview showing an image published here.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rviz/config.h>
#include <rviz/panel.h>
#include <sensor_msgs/Image.h>
#include <pluginlib/class_loader.hpp>

#include <QApplication>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <algorithm>
#include <memory>

#include "../src/rviz/mask_view.h"

namespace ar_overlay {
namespace {

template <typename Predicate>
bool SpinUntil(Predicate done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < end) {
    ros::spinOnce();  // rviz spins the global queue on its GUI thread the same way
    QCoreApplication::processEvents();
    if (done()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return false;
}

template <typename T>
bool ParamIs(const std::string& name, T want) {
  T value{};
  return ros::param::get(name, value) && value == want;
}

class TrackingPanelTest : public testing::Test {
 protected:
  pluginlib::ClassLoader<rviz::Panel> loader_{"rviz", "rviz::Panel"};
};

TEST_F(TrackingPanelTest, DeclaredAndCreatedThroughPluginlib) {
  const auto classes = loader_.getDeclaredClasses();
  ASSERT_NE(std::find(classes.begin(), classes.end(), "ar_overlay/TrackingPanel"), classes.end());
  std::unique_ptr<rviz::Panel> panel(loader_.createUnmanagedInstance("ar_overlay/TrackingPanel"));
  ASSERT_TRUE(panel);
}

TEST_F(TrackingPanelTest, DrivesPoseEkfSwitchesAndNoise) {
  std::unique_ptr<rviz::Panel> panel(loader_.createUnmanagedInstance("ar_overlay/TrackingPanel"));
  rviz::Config config;
  config.mapSetValue("EKF server", "/pose_ekf");
  config.mapSetValue("Tracker server", "/no_tracker_here");
  panel->load(config);
  panel->show();
  // The form appears once pose_ekf's latched description arrives.
  ASSERT_TRUE(SpinUntil([&] { return panel->findChild<QCheckBox*>("use_accel") != nullptr; }, 60.0))
      << "no form built from /pose_ekf/parameter_descriptions";
  for (const char* name : {"use_camera", "use_gyro", "use_accel"})
    EXPECT_TRUE(panel->findChild<QCheckBox*>(name)) << name;
  auto* gyro = panel->findChild<QCheckBox*>("use_gyro");
  auto* sigma = panel->findChild<QDoubleSpinBox*>("sigma_gyro_rad_s");
  ASSERT_TRUE(gyro && sigma);
  // The boxes show the server's values (parameter_updates), then an edit goes back.
  ASSERT_TRUE(SpinUntil([&] { return gyro->isChecked(); }, 60.0)) << "use_gyro should start on";
  gyro->setChecked(false);
  EXPECT_TRUE(SpinUntil([&] { return ParamIs("/pose_ekf/use_gyro", false); }, 60.0));
  sigma->setValue(0.05);
  EXPECT_TRUE(SpinUntil([&] { return ParamIs("/pose_ekf/sigma_gyro_rad_s", 0.05); }, 60.0));
  gyro->setChecked(true);
  EXPECT_TRUE(SpinUntil([&] { return ParamIs("/pose_ekf/use_gyro", true); }, 60.0));
  // The colour section has no server: no form, and nothing crashes.
  EXPECT_FALSE(panel->findChild<QDoubleSpinBox*>("hue_min_deg"));
}

TEST_F(TrackingPanelTest, MaskPreviewShowsTheTopic) {
  std::unique_ptr<rviz::Panel> panel(loader_.createUnmanagedInstance("ar_overlay/TrackingPanel"));
  rviz::Config config;
  config.mapSetValue("Mask topic", "/test_mask");
  panel->load(config);
  panel->show();
  auto* view = panel->findChild<MaskView*>();
  ASSERT_TRUE(view);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::Image>("/test_mask", 1);
  sensor_msgs::Image img;
  img.width = 8, img.height = 6, img.encoding = "mono8", img.step = 8;
  img.data.assign(48, 255);
  EXPECT_TRUE(SpinUntil(
      [&] {
        pub.publish(img);
        return view->frames() > 0;
      },
      60.0));
  panel->hide();  // hidden: the preview unsubscribes, so the tracker stops building debug images
  EXPECT_TRUE(SpinUntil([&] { return pub.getNumSubscribers() == 0; }, 60.0));
}

}  // namespace
}  // namespace ar_overlay

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tracking_panel");
  ros::NodeHandle nh;
  QApplication app(argc, argv);
  return RUN_ALL_TESTS();
}

#!/usr/bin/env bash
# Installs every Debian package the project needs (one list, below).
# Idempotent: only missing packages are installed, and apt-get update runs at most
# once per invocation (and not at all when nothing is missing).
# Works as root or through sudo. Usage: scripts/install_deps.sh [--print]
set -euo pipefail

PACKAGES=(
  # toolchain and tests
  build-essential cmake pkg-config googletest libgtest-dev clang-format catkin-lint
  # ROS 1 from Debian (Noetic era)
  ros-core-dev catkin rosbash python3-catkin-pkg python3-rospkg python3-rostest python3-rosbag
  libnodeletlib-dev libnodeletlib-tools pluginlib-dev
  libtf2-ros-dev libtf2-eigen-dev libtf2-geometry-msgs-dev python3-tf2-ros
  librosbag-dev libcv-bridge-dev libimage-transport-dev libcamera-info-manager-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libdiagnostic-updater-dev
  libsensor-msgs-dev libgeometry-msgs-dev libnav-msgs-dev libvisualization-msgs-dev libstd-srvs-dev
  librviz-dev rviz python3-visualization-msgs
  # maths and vision
  libeigen3-dev libceres-dev libopencv-dev libsdp-dev nlohmann-json3-dev
  # GigE camera (Aravis 0.8; its pkg-config needs libusb)
  libaravis-dev libusb-1.0-0-dev aravis-tools
  # rendering: models, headless OpenGL, a display for rviz
  libassimp-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libgles-dev xvfb
  # level of detail for dense meshes (ar_overlay)
  libmeshoptimizer-dev
  # reports
  python3-numpy python3-matplotlib python3-yaml python3-pil
  # python messages for the rostests
  python3-std-msgs python3-sensor-msgs python3-std-srvs python3-diagnostic-msgs python3-nav-msgs
  # YAML files (rig_sim's cone layouts, imu_driver's calibrations); the BROAD IMU data set's .mat files (imu_driver via scipy, pose_ekf via matio)
  libyaml-cpp-dev python3-scipy libmatio-dev
  # make demo's overlay video (OpenCV's VideoWriter, H.264); ROS's camera intrinsics calibration GUI
  python3-opencv ros-camera-calibration python3-cv-bridge python3-image-geometry
  # the base station's image viewer (ros-image-view: the node; libimage-view-dev: its package.xml, so
  # rosrun and roslaunch find it); image_transport's list_transports and republish
  ros-image-view libimage-view-dev image-transport-tools
)

if [[ "${1:-}" == "--print" ]]; then
  printf '%s\n' "${PACKAGES[@]}"
  exit 0
fi

SUDO=""
if [[ "$(id -u)" -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install_deps: not root and no sudo; run as root" >&2; exit 1; }
  SUDO="sudo"
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install_deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

echo "install_deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install_deps: done"

// A cone cut by the image's edge below a collar. The orange piece above a white or silver collar
// looks like a whole, shorter cone when the collar runs out of the image: its lower part never
// reaches the segmenter, so the border gate cannot see that the cone goes on. Fused as a whole cone
// it names a shorter layout cone (rig_sim look_away seed 4 at 12.80 s, pose_ekf README). What gives it
// away is the silhouette: between the cone's two straight edges, produced past the base, the pixels
// differ from those just outside them, all the way to the image's edge; below a real base the
// ground inside the produced edges is the ground outside them.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace cone_tracker {

// An RGB (or BGR) frame in memory; not owned.
struct RgbView {
  const uint8_t* data = nullptr;
  int width = 0, height = 0, step = 0;
};

// True when the silhouette of the cone peak -> base (pixels, base_half_width_px the half width at
// the base) continues past the base out of the image: the image's edge is at most max_run_frac
// heights past the base (a longer run would show the cone's lower part, not only a collar), and in
// at least 80 % of the rows up to it the pixels between the produced edges differ from those just
// outside them on each side by min_contrast (the largest channel's absolute difference, 0-255)
// or more. min_contrast <= 0 disables the test.
bool SilhouetteRunsOutOfImage(const RgbView& image, const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px,
                              double base_half_width_px, int min_contrast, double max_run_frac);

}  // namespace cone_tracker

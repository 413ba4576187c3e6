// The pinhole view every image-space pass shares: focal length in pixels, eye, world-to-camera
// rotation, and the world position of a pixel at a planar depth (for inputs with Z but no P).
// shaders: the same arithmetic in shadows_isg.comp, reflections_isg.comp, shadowmap_common.h.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "io/scene.h"

namespace isg::effects {

// The spacing of float32 values at magnitude |m|: 2^-23 of it, rounded down to a power of two
// (0 where m is 0, not finite, or where float32 has no normal numbers left).
inline double float32_step(double m) {
  m = std::abs(m);
  return std::isnormal(m) && std::ilogb(m) > -127 + 23 ? std::ldexp(1.0, std::ilogb(m) - 23) : 0.0;
}

// The channel that holds the refitted planar depth (of P or Z far from the world origin,
// lib/run/positions.h) while a frame is processed, bound to the depth role; never written.
inline constexpr const char* kRefitChannel = "isg:depth_from_P";

// Where the processed image lies in the camera's frame: the whole frame, or a tile of a large
// plate (lib/run/job.cpp) at (x0, y0) of a frame_w x frame_h frame. The passes take the
// principal point and the pixel hash's origin from it, so a tile computes what the same pixels
// of the whole frame would.
struct Window {
  int x0 = 0, y0 = 0, frame_w = 0, frame_h = 0;  // frame_w 0: the image is the frame
  bool whole() const { return frame_w == 0; }
  // Principal point in frame pixels (the shaders take a pixel's frame coordinates: its
  // coordinates in the w x h processed image plus the origin).
  double cx(int w) const { return 0.5 * (whole() ? w : frame_w); }
  double cy(int h) const { return 0.5 * (whole() ? h : frame_h); }
  // The hash origin for shaders: x0 | y0 << 16 (plates up to 65535 pixels a side).
  uint32_t packed_origin() const { return uint32_t(x0) | (uint32_t(y0) << 16); }
};

// The eye as the float nearest it (eye_x..) and the remainder (eye_lo_x..), into a pass's push
// constants: the shaders form P − eye as (P − eye_hi) − eye_lo (shaders/isg_view.h), exact by
// Sterbenz near the eye, so a scene far from the origin keeps the digits it has in double.
template <class Push>
void set_split_eye(Push& pc, const std::array<double, 3>& eye) {
  pc.eye_x = float(eye[0]);
  pc.eye_y = float(eye[1]);
  pc.eye_z = float(eye[2]);
  pc.eye_lo_x = float(eye[0] - double(pc.eye_x));
  pc.eye_lo_y = float(eye[1] - double(pc.eye_y));
  pc.eye_lo_z = float(eye[2] - double(pc.eye_z));
}

// The world-to-camera rotation (rows) into a pass's push constants r00..r22.
template <class Push>
void set_rotation(Push& pc, const std::array<double, 9>& m) {
  pc.r00 = float(m[0]), pc.r01 = float(m[1]), pc.r02 = float(m[2]);
  pc.r10 = float(m[3]), pc.r11 = float(m[4]), pc.r12 = float(m[5]);
  pc.r20 = float(m[6]), pc.r21 = float(m[7]), pc.r22 = float(m[8]);
}

struct PinholeView {
  double f_px = 1.0;                              // (height / 2) / tan(yfov / 2)
  std::array<double, 3> eye{0, 0, 0};             // camera centre, world
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};  // world-to-camera rotation, rows

  // For an image `height` rows tall (any resolution of the camera's frame).
  static PinholeView of(const io::Camera& cam, int height) {
    PinholeView v;
    v.f_px = 0.5 * height / std::tan(cam.yfov_deg * 3.14159265358979323846 / 360.0);
    const io::Mat4 inv = io::inverse(cam.world_to_camera);
    v.eye = {inv[3], inv[7], inv[11]};
    const auto& m = cam.world_to_camera;
    v.rot = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
    return v;
  }

  // World position of the centre of pixel i of a w x h image at planar depth z: R^T c + eye.
  std::array<double, 3> world(size_t i, double z, int w, int h) const {
    const double x = double(i % size_t(w)) + 0.5, y = double(i / size_t(w)) + 0.5;
    const double c[3] = {(x - 0.5 * w) / f_px * z, -(y - 0.5 * h) / f_px * z, -z};
    const auto& r = rot;
    return {r[0] * c[0] + r[3] * c[1] + r[6] * c[2] + eye[0],
            r[1] * c[0] + r[4] * c[1] + r[7] * c[2] + eye[1],
            r[2] * c[0] + r[5] * c[1] + r[8] * c[2] + eye[2]};
  }
};

}  // namespace isg::effects

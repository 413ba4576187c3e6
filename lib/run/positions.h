// Positions far from the world origin (issue 19): P stored as float32 steps by 2^-23 of its
// magnitude (6.25 cm 1e6 m away), several pixels at a scene radius from the camera. Within a
// surface the true positions are smooth, so the planar depth of each pixel is refitted from P's
// screen neighbours: a world plane's inverse planar depth is affine in screen coordinates, and a
// least-squares fit of 1/z over the neighbours on the pixel's surface averages P's rounding
// away. The result is a depth the effects take positions from with the camera (as from Z), so
// nothing far from the origin is formed in float.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "effects/view.h"

namespace isg::run {

// The rounding of a float32 position: each component within half its step of the truth, so the
// planar depth -R_2 . (P - eye) within `bound` of the depth of P as stored.
struct PlanarDepth {
  double z = 0;      // planar depth as stored (of P, or Z)
  double bound = 0;  // 0.5 * sum_k |R_2k| * step(P_k)
};
PlanarDepth planar_depth(const effects::PinholeView& view, const std::array<double, 3>& P);
// The same for Z as stored at pixel i of a w x h image: a renderer computes it from float32 world
// positions, the hit's and the eye's, each within half its step (Cycles 1e6 m from the origin:
// its Z as coarse as its P), so the bound is 0.5 * sum_k |R_2k| * (step(hit_k) + step(eye_k)).
PlanarDepth planar_depth_of_z(const effects::PinholeView& view, size_t i, int w, int h, double z);

// The refit is taken where P's float32 step exceeds this share of a pixel at a scene radius.
// P's rounding tilts the receiver plane each effect takes from a pixel's screen neighbours by
// up to a step over a pixel, and the map methods' error grows with it. isg-synth contact
// translated by 1e5 m (a step of 7.8 mm), key.softshadow RMSE from P against the origin's, P as
// stored -> refitted (isg, pcss, vssm, cssm): at 80x45 (0.069 pixel) +0.4 -> -0.0, +1.5 -> +1.4,
// +2.3 -> +1.6, +4.8 -> -2.1 %; at 160x90 (0.14 pixel) -0.0 -> +0.3, +3.4 -> 0.0, +3.1 -> -0.1,
// +14.1 -> -0.4 %; at 480x270 (0.41 pixel) +0.1 -> +0.3, +2.4 -> +0.3, +1.8 -> +0.3, +1.1 ->
// -0.2 %. The Cycles render of contact 1e5 m away (0.41 pixel), ratio to doing nothing over the
// pixels where Cycles does not self-shadow there (bench/shadow_cases.py), P as stored ->
// refitted: isg 0.349 -> 0.343, pcss 0.211 -> 0.212, vssm 0.205 -> 0.206, cssm 0.271 -> 0.258
// (0.353, 0.209, 0.200, 0.237 at the origin). The refit was taken only past a whole pixel
// before. Just over 1/16 (0.069 pixel) every method kept its error within 5 % without it; the
// refit costs about 0.24 us a pixel on 2 cores (0.49 s at 1920x1080).
inline constexpr double kRefitShare = 1.0 / 16.0;

// The refit's window radius (pixels) for P's step and a pixel's size at a scene radius: two
// steps' worth of pixels on either side, kRefitMinRadius to kRefitMaxRadius (the contact case
// 1e6 m away at 480x270, a step 3.3 pixels: pcss 0.237 of doing nothing with one step's worth,
// 9x9, and 0.229 with two, 15x15; 0.225 at the origin). Every pixel of the window is a sample:
// P's rounding is a staircase whose treads alias with a sparser lattice (samples 2 pixels apart
// over 13x13: pcss 0.67).
inline constexpr int kRefitMinRadius = 3;
inline constexpr int kRefitMaxRadius = 8;
int refit_radius(double step, double pixel);

// The fit's neighbours (refit_depth): a plane over those within this many bounds of the
// pixel's stored depth plus kRefitSlope pixel footprints (z / f_px) a pixel of offset, then a
// quadric over those within kRefitGate bounds of the plane. Measured (tests/unit/
// test_positions.cpp, 200x120, P's step 1.7 pixels, 7x7 window; planar depth RMS error as stored
// -> refitted): floor 0.0159 -> 0.0085 m, sphere 0.0185 -> 0.0094 (a plane in the second fit:
// 0.0062 and 0.0216, the sphere worse than P; kRefitSlope 32: 0.0091 and 0.0152).
inline constexpr double kRefitGate = 4.0;
inline constexpr double kRefitSlope = 8.0;

// Planar depth per pixel of a w x h image from P (three planes of w*h floats), or from Z
// (refit_depth_z: one plane), refitted over
// (2r+1)^2 windows of foreground pixels (fg[i] != 0): where the fits hold (twice
// as many neighbours as terms, the normal equations well posed), the inverse of the fit at the
// pixel, clamped to the pixel's bound; else the depth as stored. Background pixels take
// `background` (e.g. the input's Z; a value of ISG_BACKGROUND_DEPTH or more marks them). Threads
// over rows.
std::vector<float> refit_depth(const float* P, const float* fg, int w, int h, int r,
                               const effects::PinholeView& view, const float* background);
std::vector<float> refit_depth_z(const float* Z, const float* fg, int w, int h, int r,
                                 const effects::PinholeView& view, const float* background);

}  // namespace isg::run

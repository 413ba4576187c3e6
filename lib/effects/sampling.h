// The sampling every gather shares (image-space gathering §3.1 and its future work): a regular
// grid through the Shirley–Chiu concentric map onto the unit disk, rotated per pixel by an integer
// hash of the pixel — never of the frame, so sequences do not flicker from sampling. The double
// mirror of shaders/isg_sampling.h, for the C++ references.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace isg::effects {

// Samples per pixel rounded to a grid x grid lattice.
inline int grid_of(long long samples) {
  return std::max(1, int(std::lround(std::sqrt(double(samples)))));
}

inline uint32_t pixel_hash(uint32_t x, uint32_t y) {
  uint32_t h = (x * 0x8da6b343u) ^ (y * 0xd8163841u);
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

// The pixel's rotation of the sample grid, in [0, 2π).
inline double pixel_angle(uint32_t x, uint32_t y) {
  return double(pixel_hash(x, y)) * (2.0 * 3.14159265358979323846 / 4294967296.0);
}

// Cell k of a grid x grid lattice mapped onto the unit disk (Shirley–Chiu).
inline std::array<double, 2> concentric(int k, int grid) {
  constexpr double kPi = 3.14159265358979323846;
  const double a = 2.0 * (double(k % grid) + 0.5) / grid - 1.0;
  const double b = 2.0 * (double(k / grid) + 0.5) / grid - 1.0;
  if (a == 0.0 && b == 0.0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0) * (b / a);
  } else {
    r = b;
    phi = kPi / 2.0 - (kPi / 4.0) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// Half-resolution reuse (issue 18): bilinear weights of the pixel at (lx, ly) in its workgroup
// over the workgroup's quads x quads grid of 2x2 quads, quad q standing at its top-left pixel 2q
// (clamped at the workgroup's border). Corner k (bit 0: +x, bit 1: +y) is quad
// (qx + (k & 1), qy + (k >> 1)). The mirror of isg_quad_bilinear in shaders/isg_sampling.h.
struct QuadBilinear {
  int qx, qy;
  double ax, ay;
  double weight(int k) const { return ((k & 1) ? ax : 1.0 - ax) * ((k >> 1) ? ay : 1.0 - ay); }
};
// cell_bilinear: the same over a grid of cells_x x cells_y cells of step x step pixels
// (reflections' 4x4 blocks over the whole image; isg_cell_bilinear); a grid one cell wide keeps
// the corner at 0.
inline QuadBilinear cell_bilinear(int lx, int ly, int cells_x, int cells_y, int step) {
  const double fx = lx / double(step), fy = ly / double(step);
  const double q0x = std::clamp(std::floor(fx), 0.0, double(std::max(cells_x - 2, 0)));
  const double q0y = std::clamp(std::floor(fy), 0.0, double(std::max(cells_y - 2, 0)));
  return {int(q0x), int(q0y), std::clamp(fx - q0x, 0.0, 1.0), std::clamp(fy - q0y, 0.0, 1.0)};
}
inline QuadBilinear quad_bilinear(int lx, int ly, int quads) { return cell_bilinear(lx, ly, quads, quads, 2); }

}  // namespace isg::effects

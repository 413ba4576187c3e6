// isg-synth: the project's own ground truth. A small deterministic CPU ray tracer over analytic
// primitives that writes the AOVs `isg` reads (docs: /work/shared/AOV_CONTRACT.md) and
// distribution-ray-traced references of soft shadows, glossy reflections and depth of field.
#pragma once

#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace isg::synth {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
  friend Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
  friend Vec3 operator*(double s, Vec3 a) { return a * s; }
  friend Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
  friend Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
  Vec3& operator+=(Vec3 b) { return *this = *this + b; }
};
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return a / length(a); }
inline double luminance(Vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Diffuse albedo under a specular layer. refl.weight = spec_colour × (Schlick Fresnel with
// F0 from `ior`, or the constant `weight`); the diffuse part is scaled by 1 − that scalar.
struct Material {
  Vec3 albedo{0.5, 0.5, 0.5};
  enum class Spec { none, fresnel, constant } spec = Spec::none;
  Vec3 spec_colour{1, 1, 1};
  double ior = 1.5;        // Spec::fresnel
  double weight = 0.0;     // Spec::constant
  double roughness = 1.0;  // GGX perceptual roughness; alpha = roughness²
  Vec3 emission{};
};

// Analytic primitives. Boxes are axis-aligned; cylinders stand along +Z and are capped;
// quads are two-sided parallelograms centre ± u ± v.
struct Primitive {
  enum class Kind { sphere, box, cylinder, quad } kind = Kind::sphere;
  std::string name;
  Vec3 centre;
  double radius = 0;  // sphere, cylinder
  Vec3 half;          // box half sizes; cylinder: half.z = half height
  Vec3 u, v;          // quad half axes
  int material = 0;
  bool backdrop = false;  // far background: left out of scene_radius (the set's scale, not the sky's)
};

// A named light; its AOVs are `<name>.shadow`, `<name>.occluder`, `<name>.direct.R/G/B`.
// For the AOVs a sphere, disk, rect or spot light is a point at `position`: isotropic intensity
// for a sphere light, intensity × max(0, cos to `normal`) for disk and rect lights (a Lambertian
// emitter shrunk to a point), so the area light of the references, radiance intensity / area, has
// the same total power and gives an unoccluded point the same direct light up to (r/d)². A spot
// is a sphere light's isotropic intensity shaped by Blender's cone (spot_attenuation). A sun is
// distant: irradiance × cos along `direction`, its disk `angle_deg` wide in the references.
struct Light {
  enum class Type { sphere, disk, rect, spot, sun } type = Type::sphere;
  Vec3 position;                  // every type but sun
  double radius = 0.3;            // sphere, disk, spot
  Vec3 normal{0, 0, -1};          // disk, rect: the emitting side; spot: the way it shines
  Vec3 u_axis{1, 0, 0};           // rect
  double size_u = 1, size_v = 1;  // rect
  Vec3 intensity{50, 50, 50};     // W/sr along the normal (isotropic: sphere; on the axis: spot);
                                  // sun: irradiance, W/m² on a surface facing it
  std::string name = "key";
  double spot_angle_deg = 60;  // spot: the cone's full angle (Blender's spot size)
  double spot_blend = 0.15;    // spot: 0 to 1 (Blender's blend)
  Vec3 direction{0, 0, 1};     // sun: unit, from the scene toward the sun
  double angle_deg = 0.53;     // sun: the full angle its disk subtends
};

// Blender/Cycles' spot cone (kernel/light/spot.h, scene/light.cpp): smoothstep((cos θ −
// cos(size/2)) / ((1 − cos(size/2))·blend)), θ from the axis; blend 0: a hard edge.
double spot_attenuation(const Light& spot, Vec3 dir_from_light);

struct Camera {
  Vec3 position, target;
  int width = 640, height = 360;
  double focal_length_mm = 40, sensor_width_mm = 36;  // horizontal fit
  double fstop = 2.8, focus_distance = 5;             // focus_distance: planar, world units
  double near = 0.1, far = 100;
};

// The parallel-planes configuration, for the closed form: receiver plane z = receiver_z,
// occluder half-plane z = occluder_z covering x < edge_x, disk light parallel to both.
struct ParallelPlanes {
  double receiver_z = 0, occluder_z = 1, edge_x = 0;
};

struct Scene {
  std::string name;
  std::vector<Material> materials;
  std::vector<Primitive> prims;
  // Names unique; lights[0] is "key" in every scene but sun and spot.
  std::vector<Light> lights;
  Camera camera;
  Vec3 fill{0.07, 0.075, 0.085};  // uniform world: ambient = kd·albedo·fill, reflection misses
  bool depth_of_field = false;    // the beauty reference uses the thin lens
  std::optional<ParallelPlanes> parallel_planes;
};

struct Options {
  std::string scene = "contact";
  int width = 640, height = 360;
  int aov_spp = 1;    // 1: pixel centres; N: box-filtered average of N stratified samples
  int ref_spp = 256;  // samples per pixel of every reference
  std::optional<double> light_radius;  // overrides the first light's (rect: half the u size)
  std::optional<double> sun_angle;     // overrides every sun's angle_deg
  std::optional<double> roughness;     // overrides every glossy surface's roughness
  std::optional<double> fstop;         // overrides the scene's; turns on DOF in ref/beauty.exr
  int frame = 0;                       // moves the scene's moving object
  int threads = 0;                     // 0: hardware concurrency
  int shadowmap_size = 1024;
  bool refs = true;        // write ref/
  bool stratified = true;  // stratified light / lens samples in the references
};

// A float image with named channels, interleaved.
struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;
  Image() = default;
  Image(int w, int h, std::vector<std::string> names);
  int channel(const std::string& name) const;  // throws when absent
  float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels.size() + c]; }
  float at(int x, int y, int c) const {
    return pixels[(size_t(y) * width + x) * channels.size() + c];
  }
};

std::vector<std::string> scene_names();
std::string scene_description(const std::string& name);
void validate(const Options& opts);      // throws std::runtime_error naming the option
Scene build_scene(const Options& opts);  // validates, applies overrides and --frame

// Camera and light matrices, row-major, column-vector convention (p_cam = M · p_world), as in
// scene.json. Cameras look down −Z with +Y up.
std::array<double, 16> world_to_camera(const Camera& cam);
// A light's shadow map: perspective from `position` (sphere, disk, rect: toward the camera's
// target, 90°; spot: down its axis), or orthographic for a sun (looking down −Z along
// −direction from beyond the scene's bounding sphere, covering it).
struct ShadowMapView {
  std::array<double, 16> world_to_light;
  bool orthographic = false;
  double yfov_deg = 90;              // perspective
  double width_m = 0, height_m = 0;  // orthographic
  double near = 0.05, far = 100;
};
ShadowMapView shadowmap_view(const Scene& scene, size_t light = 0);
std::array<double, 16> world_to_light(const Scene& scene, size_t light = 0);
// OpenGL-style projection (x, y in [−1, 1] over the image, +y up; z −1 at near, +1 at far) ·
// world_to_camera.
std::array<double, 16> world_to_ndc(const Camera& cam);
double yfov_deg(const Camera& cam);
double scene_radius(const Scene& scene);
// The bounding sphere of the non-backdrop primitives (their bounding boxes' corners).
std::pair<Vec3, double> bounding_sphere(const Scene& scene);

// In-memory renders (threads from opts.threads; results do not depend on it).
// render_aovs: the contract's channels, `<name>.shadow/occluder/direct.R/G/B` for each light in
// order, plus `other.R/G/B` (emission + ambient, the part of beauty outside
// Σ direct·shadow + refl.weight·refl), which generate() does not write.
Image render_aovs(const Scene& scene, const Options& opts);
Image render_shadowmap(const Scene& scene, int size, size_t light = 0);  // channel Z
// <name>.softshadow of lights[light]: the luminance ratio of the soft light to the unshadowed
// one, `spp` light samples per pixel over the light's area (sphere: the disk of its radius facing
// the point; sun: directions over its disk): the visible fraction of the light weighted by the
// irradiance each of its points gives.
Image render_softshadow(const Scene& scene, const Options& opts, int spp, size_t light = 0);
// key.softshadow from the closed form (parallel-planes only; throws otherwise).
Image render_softshadow_closed_form(const Scene& scene, const Options& opts);
// Closed form: the fraction of a disk of radius R beyond a chord at signed distance d from its
// centre, {x > d} (d ≥ R: 0, d ≤ −R: 1): the visible part where the rest is hidden.
double disk_visible_fraction(double d, double R);
// The share of the irradiance a receiver at p with normal n gets from a light disk (centre
// `centre`, orthonormal in-plane axes u and v, radius R, emitting from both faces) that comes from
// the part beyond the chord {x·u > c}: ∫ max(n·r, 0) |n_l·r| / |r|⁴ over that part over the same
// over the disk (r from p to the light point, n_l = u × v), by Gauss-Legendre quadrature in double.
// The uniform fraction disk_visible_fraction(c, R) where no part of the disk lights p.
double disk_irradiance_beyond_chord(Vec3 p, Vec3 n, Vec3 centre, Vec3 u, Vec3 v, double R, double c);
Image render_glossy(const Scene& scene, const Options& opts, int spp);      // refl.glossy.R/G/B
Image render_dof(const Scene& scene, const Options& opts, int spp);         // R G B A
Image render_beauty_ref(const Scene& scene, const Options& opts, int spp);  // R G B A

// Adds `mask` to a reference: the softshadow mask (foreground, <light>.direct luminance ≥ 2 % of
// its 99th percentile), the glossy mask (refl.weight > 0) or the foreground (A > 0.5).
enum class MaskKind { softshadow, glossy, foreground };
void add_mask(Image& ref, const Image& aovs, MaskKind kind, const std::string& light = "key");

struct Timing {
  std::string file;
  double seconds = 0;
};
// Writes aovs.exr, shadowmap_<light>.exr for each light, scene.json and (opts.refs) ref/*.exr
// into out_dir.
std::vector<Timing> generate(const Options& opts, const std::filesystem::path& out_dir);

}  // namespace isg::synth

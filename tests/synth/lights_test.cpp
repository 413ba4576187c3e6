// Several named lights, the sun and the spot: each against a truth computed here from the
// geometry (the sun's penumbra, Blender's spot cone, the orthographic shadow map) and the
// multi-light AOVs against the one-light scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "synth.h"

namespace {

using namespace isg::synth;

constexpr double kPi = std::numbers::pi;

Options small(const std::string& scene, int w, int h) {
  Options o;
  o.scene = scene;
  o.width = w;
  o.height = h;
  o.threads = 2;
  return o;
}

// The light-space position of P: x, y and the planar depth −z (p_light = M · P).
std::array<double, 3> to_light(const std::array<double, 16>& m, const Image& aovs, int x, int y) {
  const int cP = aovs.channel("P.X");
  const double P[4] = {aovs.at(x, y, cP), aovs.at(x, y, cP + 1), aovs.at(x, y, cP + 2), 1};
  double q[3] = {0, 0, 0};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) q[r] += m[size_t(r * 4 + c)] * P[c];
  return {q[0], q[1], -q[2]};
}

// A sun 60° high, tilted along the edge of a half-plane occluder (x < 0 at height h) over a
// floor, seen from below the occluder with a 50 mm lens so that the penumbra spans pixels.
Scene sun_over_half_plane(double h, double angle_deg) {
  Scene s;
  s.name = "sun-half-plane";
  s.materials = {Material{}};
  Primitive floor;
  floor.kind = Primitive::Kind::quad;
  floor.name = "floor";
  floor.u = {10, 0, 0};
  floor.v = {0, 10, 0};
  Primitive occ = floor;
  occ.name = "occluder";
  occ.centre = {-5, 0, h};
  occ.u = {5, 0, 0};
  s.prims = {floor, occ};
  Light sun;
  sun.type = Light::Type::sun;
  sun.name = "sun";
  const double e = 60 * kPi / 180;
  sun.direction = {0, -std::cos(e), std::sin(e)};
  sun.angle_deg = angle_deg;
  sun.intensity = {3, 3, 3};
  s.lights = {sun};
  s.camera.position = {0, -1.2, 1.0};
  s.camera.target = {0, 0, 0};
  s.camera.focal_length_mm = 50;
  s.camera.width = 160;
  s.camera.height = 90;
  return s;
}

// The reference soft shadow of a sun over a half-plane is the visible fraction of its disk beyond
// the chord that the plane through P and the occluder's edge cuts: seen from P (x, y, 0), that
// plane has the normal m = (h, 0, x)/√(h² + x²), lit directions have m·ω > 0, and in the tangent
// (gnomonic) plane of the sun's direction c the disk is a circle of radius tan(angle/2) cut by a
// line at distance tan(asin(m·c)) from its centre. The receiver's cosine varies across the disk
// only along the edge (the tilt is along it), so it cancels to first order.
TEST(Sun, PenumbraMatchesClosedForm) {
  const double h = 1.5, angle = 4.0;
  const Scene s = sun_over_half_plane(h, angle);
  Options o = small("sun", 160, 90);
  const Image aovs = render_aovs(s, o);
  const Image soft = render_softshadow(s, o, 256);
  ASSERT_EQ(soft.channels, std::vector<std::string>{"sun.softshadow"});
  const double R = std::tan(0.5 * angle * kPi / 180);
  const Vec3 c = s.lights[0].direction;
  const int cA = aovs.channel("A"), cP = aovs.channel("P.X"), cs = aovs.channel("sun.shadow"),
            co = aovs.channel("sun.occluder");
  double sum = 0, worst = 0;
  int penumbra = 0, n = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (aovs.at(x, y, cA) < 1) continue;
      const double px = aovs.at(x, y, cP), pz = aovs.at(x, y, cP + 2);
      ASSERT_NEAR(pz, 0.0, 1e-6);  // the camera sees only the floor
      const Vec3 m = Vec3{h, 0, px} / std::hypot(h, px);
      const double want = disk_visible_fraction(-std::tan(std::asin(dot(m, c))), R);
      const double got = soft.at(x, y, 0), err = std::abs(got - want);
      sum += err * err;
      worst = std::max(worst, err);
      ++n;
      penumbra += want > 0.05 && want < 0.95;
      // The AOVs: hard from the sun's centre, the occluder h / sin(elevation) away along it.
      EXPECT_EQ(aovs.at(x, y, cs), px < 0 ? 0.0f : 1.0f) << x << "," << y;
      EXPECT_NEAR(aovs.at(x, y, co), px < 0 ? h / c.z : 0.0, 1e-5);
    }
  const double rmse = std::sqrt(sum / n);
  std::printf("sun penumbra: %d px, RMSE %.5f, max %.5f against the closed form\n", penumbra, rmse,
              worst);
  ASSERT_GT(penumbra, 1000);
  EXPECT_LT(rmse, 0.004);
  EXPECT_LT(worst, 0.05);
}

// Blender's spot cone (Cycles' spot_light_attenuation with scene/light.cpp's spot_smooth):
// smoothstep((cos θ − cos(size/2)) / ((1 − cos(size/2))·blend)), written out here.
double blender_spot(double cos_theta, double size_deg, double blend) {
  const double cos_half = std::cos(size_deg * kPi / 360);
  const double x = (cos_theta - cos_half) / ((1 - cos_half) * blend);
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  return x * x * (3 - 2 * x);
}

// spot.direct is the same light without its cone (a sphere light of the same intensity) times
// Blender's falloff at P: 1 inside the cone, the smoothstep in the blend, 0 outside.
TEST(Spot, DirectFollowsBlenderFalloff) {
  const Options o = small("spot", 160, 90);
  const Scene s = build_scene(o);
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& spot = s.lights[0];
  ASSERT_EQ(spot.type, Light::Type::spot);
  Scene bare = s;
  bare.lights[0].type = Light::Type::sphere;
  const Image a = render_aovs(s, o), b = render_aovs(bare, o);
  const int cA = a.channel("A"), cd = a.channel("spot.direct.R"), cP = a.channel("P.X");
  int inside = 0, blend = 0, outside = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const double unshaped = b.at(x, y, cd);
      if (a.at(x, y, cA) < 1 || unshaped <= 1e-6) continue;
      const Vec3 P{a.at(x, y, cP), a.at(x, y, cP + 1), a.at(x, y, cP + 2)};
      const double cos_theta = dot(normalize(spot.normal), normalize(P - spot.position));
      const double want = blender_spot(cos_theta, spot.spot_angle_deg, spot.spot_blend);
      // P is stored in float: its rounding moves the falloff by ~1e-6.
      EXPECT_NEAR(a.at(x, y, cd) / unshaped, want, 2e-4) << x << "," << y;
      inside += want == 1;
      outside += want == 0;
      blend += want > 0.05 && want < 0.95;
      if (want == 0) {
        EXPECT_EQ(a.at(x, y, cd), 0.0f);
      }
    }
  std::printf("spot: %d px inside the cone, %d in the blend, %d outside\n", inside, blend, outside);
  EXPECT_GT(inside, 1000);
  EXPECT_GT(blend, 300);
  EXPECT_GT(outside, 300);
  // The cone shapes the AOV and the references alike: the soft shadow is the disk's, 1 where
  // nothing is in the way, even in the blend.
  const Image soft = render_softshadow(s, o, 4);
  const int cs = a.channel("spot.shadow");
  int lit = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      if (a.at(x, y, cs) == 1 && a.at(x, y, cd) > 0 && soft.at(x, y, 0) == 1) ++lit;
  EXPECT_GT(lit, 2000);
}

// three-lights: contact's key untouched by the other two, the sun's channels those of the sun
// scene scaled by its irradiance, and the beauty the sum over the lights.
TEST(ThreeLights, EachLightItsOwnChannels) {
  const Options o3 = small("three-lights", 96, 54), oc = small("contact", 96, 54),
                os = small("sun", 96, 54);
  const Scene s3 = build_scene(o3), sc = build_scene(oc), ss = build_scene(os);
  ASSERT_EQ(s3.lights.size(), 3u);
  const Image a3 = render_aovs(s3, o3), ac = render_aovs(sc, oc), as = render_aovs(ss, os);
  const double scale = s3.lights[1].intensity.x / ss.lights[0].intensity.x;
  auto same = [&](const Image& a, const std::string& ca, const Image& b, const std::string& cb,
                  double k) {
    const int ia = a.channel(ca), ib = b.channel(cb);
    double worst = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        worst = std::max(worst, std::abs(a.at(x, y, ia) - k * b.at(x, y, ib)));
    return worst;
  };
  for (const char* ch : {"key.shadow", "key.occluder", "key.direct.R", "key.direct.G",
                         "key.direct.B", "refl.weight.R", "other.G"})
    EXPECT_EQ(same(a3, ch, ac, ch, 1), 0.0) << ch;
  for (const char* ch : {"sun.shadow", "sun.occluder"})
    EXPECT_EQ(same(a3, ch, as, ch, 1), 0.0) << ch;
  for (const char* ch : {"sun.direct.R", "sun.direct.G", "sun.direct.B"})
    EXPECT_LT(same(a3, ch, as, ch, scale), 1e-6) << ch;
  EXPECT_EQ(render_softshadow(s3, o3, 16, 0).pixels, render_softshadow(sc, oc, 16).pixels);

  const int cR = a3.channel("R"), cw = a3.channel("refl.weight.R"), cr = a3.channel("refl.R"),
            cO = a3.channel("other.R"), cA = a3.channel("A");
  int fill_lit = 0;
  for (int y = 0; y < a3.height; ++y)
    for (int x = 0; x < a3.width; ++x) {
      if (a3.at(x, y, cA) < 1) continue;
      fill_lit += a3.at(x, y, a3.channel("fill.direct.G")) > 0;
      for (int c = 0; c < 3; ++c) {
        double want =
            double(a3.at(x, y, cO + c)) + double(a3.at(x, y, cw + c)) * a3.at(x, y, cr + c);
        for (const auto& l : s3.lights)
          want += double(a3.at(x, y, a3.channel(l.name + ".direct.R") + c)) *
                  a3.at(x, y, a3.channel(l.name + ".shadow"));
        EXPECT_NEAR(a3.at(x, y, cR + c), want, 1e-5 + 1e-6 * want);
      }
    }
  EXPECT_GT(fill_lit, a3.width * a3.height / 2);
}

// The contract's composite, summed over the three lights, reproduces the full reference (every
// light soft in ref/beauty): each light's references and AOVs are separable.
TEST(ThreeLights, OracleCompositeMatchesBeauty) {
  const Options o = small("three-lights", 96, 54);
  const Scene s = build_scene(o);
  const Image aovs = render_aovs(s, o);
  const int spp = 100;
  std::vector<Image> soft;
  for (size_t k = 0; k < s.lights.size(); ++k) soft.push_back(render_softshadow(s, o, spp, k));
  const Image gloss = render_glossy(s, o, spp), ref = render_beauty_ref(s, o, spp);
  const int cR = aovs.channel("R"), cw = aovs.channel("refl.weight.R"), cr = aovs.channel("refl.R");
  double err = 0, hard = 0;
  int n = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double beauty = aovs.at(x, y, cR + c);
        double comp = beauty + aovs.at(x, y, cw + c) * (gloss.at(x, y, c) - aovs.at(x, y, cr + c));
        for (size_t k = 0; k < s.lights.size(); ++k) {
          const std::string& name = s.lights[k].name;
          comp += aovs.at(x, y, aovs.channel(name + ".direct.R") + c) *
                  (soft[k].at(x, y, 0) - aovs.at(x, y, aovs.channel(name + ".shadow")));
        }
        err += std::pow(comp - ref.at(x, y, c), 2);
        hard += std::pow(beauty - ref.at(x, y, c), 2);
        ++n;
      }
  err = std::sqrt(err / n);
  hard = std::sqrt(hard / n);
  std::printf("three-lights oracle composite RMSE %.5f, hard AOV beauty RMSE %.5f\n", err, hard);
  EXPECT_LT(err, 0.012);
  EXPECT_LT(err, 0.5 * hard);
}

// The sun's orthographic map: it covers every receiver, lit receivers find their own planar
// depth along the axis, umbra receivers a closer one; the map camera looks down −direction.
TEST(ShadowMap, SunOrthographicAgreesWithHardShadows) {
  const Options o = small("sun", 128, 72);
  const Scene s = build_scene(o);
  const ShadowMapView v = shadowmap_view(s, 0);
  ASSERT_TRUE(v.orthographic);
  const auto& m = v.world_to_light;
  const Vec3 d = s.lights[0].direction;
  EXPECT_NEAR(m[8], d.x, 1e-12);
  EXPECT_NEAR(m[9], d.y, 1e-12);
  EXPECT_NEAR(m[10], d.z, 1e-12);
  EXPECT_EQ(v.near, 0.0);
  const int size = 1024;
  const Image map = render_shadowmap(s, size, 0);
  const Image aovs = render_aovs(s, o);
  const int cs = aovs.channel("sun.shadow"), cA = aovs.channel("A"),
            cd = aovs.channel("sun.direct.R");
  const double texel = v.width_m / size;
  int lit = 0, lit_ok = 0, umbra = 0, umbra_ok = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (aovs.at(x, y, cA) == 0) continue;
      const auto q = to_light(m, aovs, x, y);
      ASSERT_GT(q[2], v.near);
      ASSERT_LT(q[2], v.far);
      const double fu = (q[0] / (0.5 * v.width_m) + 1) * 0.5 * size;
      const double fv = (1 - q[1] / (0.5 * v.height_m)) * 0.5 * size;
      ASSERT_TRUE(fu >= 0 && fv >= 0 && fu < size && fv < size) << x << "," << y;
      if (aovs.at(x, y, cd) <= 0) continue;
      const double stored = map.at(int(fu), int(fv), 0);
      // A texel away the floor's depth moves by texel·tan(incidence) (60° here).
      if (aovs.at(x, y, cs) == 1)
        ++lit, lit_ok += std::abs(stored - q[2]) < 3 * texel;
      else
        ++umbra, umbra_ok += stored < q[2] - 3 * texel;
    }
  ASSERT_GT(lit, 1000);
  ASSERT_GT(umbra, 100);
  EXPECT_GT(lit_ok, 0.95 * lit);
  EXPECT_GT(umbra_ok, 0.95 * umbra);
}

// The spot's perspective map looks down its axis.
TEST(ShadowMap, SpotLooksDownItsAxis) {
  const Scene s = build_scene(small("spot", 32, 18));
  const ShadowMapView v = shadowmap_view(s, 0);
  EXPECT_FALSE(v.orthographic);
  EXPECT_EQ(v.yfov_deg, 90.0);
  const Vec3 a = normalize(s.lights[0].normal);
  EXPECT_NEAR(-v.world_to_light[8], a.x, 1e-12);
  EXPECT_NEAR(-v.world_to_light[9], a.y, 1e-12);
  EXPECT_NEAR(-v.world_to_light[10], a.z, 1e-12);
}

TEST(Options, SunAngleAndLightRadius) {
  Options o = small("three-lights", 32, 18);
  o.sun_angle = 1.0;
  EXPECT_EQ(build_scene(o).lights[1].angle_deg, 1.0);
  o.scene = "contact";
  EXPECT_THROW(build_scene(o), std::runtime_error);
  o = small("sun", 32, 18);
  o.light_radius = 0.2;
  try {
    build_scene(o);
    ADD_FAILURE() << "--light-radius on a sun accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--light-radius"), std::string::npos) << e.what();
  }
  o = small("three-lights", 32, 18);
  o.light_radius = 0.2;
  EXPECT_EQ(build_scene(o).lights[0].radius, 0.2);
}

}  // namespace

// The renderer against the closed form, its own invariants and the far-world scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "synth.h"

namespace {

using namespace isg::synth;

Options small(const std::string& scene, int w = 128, int h = 72) {
  Options o;
  o.scene = scene;
  o.width = w;
  o.height = h;
  o.threads = 2;
  return o;
}

double rmse_over(const Image& a, int ca, const Image& b, int cb, const Image& mask, int cm) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (mask.at(x, y, cm) < 0.5f) continue;
      const double d = double(a.at(x, y, ca)) - b.at(x, y, cb);
      sum += d * d;
      ++n;
    }
  return n ? std::sqrt(sum / n) : 0.0;
}

TEST(ClosedForm, DiskVisibleFraction) {
  EXPECT_NEAR(disk_visible_fraction(0, 2), 0.5, 1e-12);
  EXPECT_NEAR(disk_visible_fraction(2, 2), 0.0, 1e-12);
  EXPECT_NEAR(disk_visible_fraction(-2, 2), 1.0, 1e-12);
  EXPECT_NEAR(disk_visible_fraction(5, 2), 0.0, 1e-12);
  for (double d : {0.1, 0.5, 1.3, 1.9}) {
    EXPECT_NEAR(disk_visible_fraction(d, 2) + disk_visible_fraction(-d, 2), 1.0, 1e-12);
    // Numerical integral of the chord length √(R²−x²)·2 beyond d.
    double area = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const double x = d + (2 - d) * (i + 0.5) / n;
      area += 2 * std::sqrt(4 - x * x) * (2 - d) / n;
    }
    EXPECT_NEAR(disk_visible_fraction(d, 2), area / (std::numbers::pi * 4), 1e-5);
  }
}

// The irradiance-weighted share of a light disk beyond a chord (the quadrature of the
// closed-form soft shadow) against a midpoint sum over a fine grid of the disk, and against the
// uniform fraction where the weight is nearly constant (a light far away).
TEST(ClosedForm, DiskIrradianceBeyondChord) {
  const Vec3 centre{0.2, -0.1, 1.0}, u{1, 0, 0}, v{0, 1, 0};
  const double R = 0.5;
  auto brute = [&](Vec3 p, Vec3 n, double c) {
    const int m = 1500;
    double all = 0, part = 0;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const double x = R * (2.0 * (i + 0.5) / m - 1), y = R * (2.0 * (j + 0.5) / m - 1);
        if (x * x + y * y > R * R) continue;
        const Vec3 r = centre + u * x + v * y - p;
        const double r2 = dot(r, r), w = std::max(dot(n, r), 0.0) * std::abs(r.z) / (r2 * r2);
        all += w;
        if (x > c) part += w;
      }
    return part / all;
  };
  // A receiver under the light, tilted; one the light stands low over (part of the disk below
  // its horizon, where the weight has a kink).
  const Vec3 tilted = normalize(Vec3{0.3, 0.1, 1.0}), low = normalize(Vec3{1.0, 0.0, 0.35});
  for (double c : {-0.3, 0.0, 0.2, 0.45}) {
    EXPECT_NEAR(disk_irradiance_beyond_chord({0.5, 0.3, 0}, tilted, centre, u, v, R, c),
                brute({0.5, 0.3, 0}, tilted, c), 2e-5) << c;
    EXPECT_NEAR(disk_irradiance_beyond_chord({-1.5, 0.0, 0.8}, low, centre, u, v, R, c),
                brute({-1.5, 0.0, 0.8}, low, c), 2e-3) << c;
    EXPECT_NEAR(disk_irradiance_beyond_chord({0.2, -0.1, -1e4}, {0, 0, 1}, centre, u, v, R, c),
                disk_visible_fraction(c, R), 1e-6) << c;
  }
  // Weighted toward the side the receiver faces: its top lights a floor more than its bottom.
  EXPECT_GT(disk_irradiance_beyond_chord({0.2, -0.1, 0}, tilted, centre, u, v, R, 0.0), 0.5);
}

// The ray-traced soft visibility converges to the closed form like 1/√N (independent light
// samples), and faster with stratified samples.
TEST(ParallelPlanes, SoftShadowConvergesToClosedForm) {
  Options o = small("parallel-planes");
  const Scene s = build_scene(o);
  const Image aovs = render_aovs(s, o);
  Image exact = render_softshadow_closed_form(s, o);
  add_mask(exact, aovs, MaskKind::softshadow);
  const int m = exact.channel("mask");
  // The mask must contain a real penumbra.
  int penumbra = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      if (exact.at(x, y, m) > 0.5f && exact.at(x, y, 0) > 0.05f && exact.at(x, y, 0) < 0.95f)
        ++penumbra;
  ASSERT_GT(penumbra, 500);

  o.stratified = false;
  std::vector<double> logn, loge;
  double last = 0;
  for (int n : {16, 64, 256}) {
    const Image rt = render_softshadow(s, o, n);
    last = rmse_over(rt, 0, exact, 0, exact, m);
    logn.push_back(std::log(double(n)));
    loge.push_back(std::log(last));
  }
  const double slope = (loge[2] - loge[0]) / (logn[2] - logn[0]);
  std::printf("RMSE(N): %.5f %.5f %.5f, slope %.3f\n", std::exp(loge[0]), std::exp(loge[1]), last,
              slope);
  EXPECT_NEAR(slope, -0.5, 0.1) << "RMSE at 256: " << last;
  EXPECT_LT(last, 0.02);

  o.stratified = true;
  const double strat = rmse_over(render_softshadow(s, o, 256), 0, exact, 0, exact, m);
  std::printf("stratified RMSE at 256: %.5f\n", strat);
  EXPECT_LT(strat, 0.5 * last);
  EXPECT_LT(strat, 0.005);
}

TEST(FarWorld, SameImagesAsContact) {
  const Options oc = small("contact", 96, 54), of = small("far-world", 96, 54);
  const Scene sc = build_scene(oc), sf = build_scene(of);
  const Image ac = render_aovs(sc, oc), af = render_aovs(sf, of);
  for (const char* ch : {"R", "G", "B", "A", "Z", "N.Z", "key.shadow", "refl.G", "refl.dist"}) {
    const int c = ac.channel(ch);
    double worst = 0;
    for (size_t i = 0; i < ac.pixels.size() / ac.channels.size(); ++i) {
      const size_t k = i * ac.channels.size() + size_t(c);
      worst = std::max(worst, double(std::abs(ac.pixels[k] - af.pixels[k])));
    }
    EXPECT_LT(worst, 1e-4) << ch;
  }
  // P differs by the translation, up to float32 storage at 1e5 (ulp 0.0078).
  const int px = ac.channel("P.X"), a = ac.channel("A");
  for (int y = 0; y < ac.height; ++y)
    for (int x = 0; x < ac.width; ++x)
      if (ac.at(x, y, a) > 0) {
        EXPECT_NEAR(af.at(x, y, px) - 1e5, ac.at(x, y, px), 0.01);
      }

  const Image ssc = render_softshadow(sc, oc, 16), ssf = render_softshadow(sf, of, 16);
  const Image gc = render_glossy(sc, oc, 16), gf = render_glossy(sf, of, 16);
  size_t differ = 0;
  for (size_t i = 0; i < ssc.pixels.size(); ++i)
    differ += std::abs(ssc.pixels[i] - ssf.pixels[i]) > 1e-4f;
  for (size_t i = 0; i < gc.pixels.size(); ++i)
    differ += std::abs(gc.pixels[i] - gf.pixels[i]) > 1e-4f;
  // Rays hitting exactly an edge may flip; allow a handful of values out of 20736.
  EXPECT_LE(differ, 5u);
}

// depth-range: contact's pixels are unchanged where contact had geometry, the rest is the
// backdrop at planar depth ~1e6 (lit, finite), and scene_radius ignores the backdrop.
TEST(DepthRange, ContactBeforeAFarBackdrop) {
  const Options oc = small("contact", 96, 54), od = small("depth-range", 96, 54);
  const Scene sc = build_scene(oc), sd = build_scene(od);
  EXPECT_EQ(scene_radius(sd), scene_radius(sc));
  const Image ac = render_aovs(sc, oc), ad = render_aovs(sd, od);
  const int z = ac.channel("Z"), a = ac.channel("A"), ks = ac.channel("key.shadow");
  size_t wall = 0;
  for (int y = 0; y < ac.height; ++y)
    for (int x = 0; x < ac.width; ++x) {
      if (ac.at(x, y, a) > 0) {
        EXPECT_EQ(ad.at(x, y, z), ac.at(x, y, z));
        continue;
      }
      ++wall;
      EXPECT_EQ(ad.at(x, y, a), 1.0f);
      EXPECT_GT(ad.at(x, y, z), 0.9e6f);
      EXPECT_LT(ad.at(x, y, z), 1.5e6f);
      EXPECT_EQ(ad.at(x, y, ks), 1.0f);
    }
  EXPECT_GT(wall, size_t(ac.width * ac.height / 20));
}

TEST(Aovs, ConsistentSingleSample) {
  const Options o = small("contact");
  const Scene s = build_scene(o);
  const Image img = render_aovs(s, o);
  const auto m = world_to_camera(s.camera);
  const double tan_x = s.camera.sensor_width_mm / (2 * s.camera.focal_length_mm);
  const double tan_y = tan_x * o.height / o.width;
  const int cA = img.channel("A"), cZ = img.channel("Z"), cP = img.channel("P.X"),
            cN = img.channel("N.X"), cs = img.channel("key.shadow"),
            co = img.channel("key.occluder"), cd = img.channel("key.direct.R"),
            cw = img.channel("refl.weight.R"), cr = img.channel("refl.R"),
            cO = img.channel("other.R"), cR = img.channel("R"), cdist = img.channel("refl.dist");
  int fg = 0, shadowed = 0, reflective = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (img.at(x, y, cA) == 0) {  // background
        EXPECT_EQ(img.at(x, y, cZ), 1e10f);
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(img.at(x, y, cP + c), 0.0f);
          EXPECT_EQ(img.at(x, y, cN + c), 0.0f);
          EXPECT_EQ(img.at(x, y, cR + c), 0.0f);
        }
        continue;
      }
      ++fg;
      ASSERT_EQ(img.at(x, y, cA), 1.0f);
      const double P[4] = {img.at(x, y, cP), img.at(x, y, cP + 1), img.at(x, y, cP + 2), 1};
      double q[3] = {0, 0, 0};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) q[r] += m[size_t(r * 4 + c)] * P[c];
      EXPECT_NEAR(-q[2], img.at(x, y, cZ), 1e-5 * img.at(x, y, cZ));
      const double px = (q[0] / -q[2] / tan_x + 1) * 0.5 * o.width;
      const double py = (1 - q[1] / -q[2] / tan_y) * 0.5 * o.height;
      EXPECT_NEAR(px, x + 0.5, 0.01);
      EXPECT_NEAR(py, y + 0.5, 0.01);
      const float shadow = img.at(x, y, cs), occ = img.at(x, y, co);
      EXPECT_TRUE(shadow == 0.0f || shadow == 1.0f);
      EXPECT_EQ(shadow == 0.0f, occ > 0.0f);
      shadowed += shadow == 0.0f;
      reflective += img.at(x, y, cw) > 0;
      if (img.at(x, y, cw) > 0 && img.at(x, y, cdist) > 0) {
        EXPECT_LT(img.at(x, y, cdist), 30.0f);
      }
      for (int c = 0; c < 3; ++c) {
        const double want = double(img.at(x, y, cO + c)) + double(img.at(x, y, cd + c)) * shadow +
                            double(img.at(x, y, cw + c)) * img.at(x, y, cr + c);
        EXPECT_NEAR(img.at(x, y, cR + c), want, 1e-5 + 1e-6 * want);
      }
    }
  EXPECT_GT(fg, o.width * o.height / 2);
  EXPECT_GT(shadowed, 100);
  EXPECT_GT(reflective, 100);
}

TEST(Aovs, AntiAliasedCoverageAndUnpremultipliedGeometry) {
  Options o = small("contact", 96, 54);
  o.aov_spp = 9;
  const Image img = render_aovs(build_scene(o), o);
  const int cA = img.channel("A"), cN = img.channel("N.X"), cr = img.channel("roughness"),
            cs = img.channel("key.shadow");
  int partial = 0, soft_edge = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const float a = img.at(x, y, cA);
      ASSERT_GE(a, 0.0f);
      ASSERT_LE(a, 1.0f);
      partial += a > 0 && a < 1;
      const float s = img.at(x, y, cs);
      soft_edge += s > 0 && s < 1;
      if (a == 0) continue;
      const double n = std::hypot(img.at(x, y, cN), img.at(x, y, cN + 1), img.at(x, y, cN + 2));
      EXPECT_NEAR(n, 1.0, 1e-3);
      EXPECT_GE(img.at(x, y, cr), 0.0f);
      EXPECT_LE(img.at(x, y, cr), 1.0f);
    }
  EXPECT_GT(partial, 20);
  EXPECT_GT(soft_edge, 20);
}

TEST(Glossy, ZeroRoughnessEqualsSharpReflection) {
  Options o = small("gloss", 96, 54);
  o.roughness = 1e-4;
  const Scene s = build_scene(o);
  const Image aovs = render_aovs(s, o);
  Image g = render_glossy(s, o, 4);
  add_mask(g, aovs, MaskKind::glossy);
  const int m = g.channel("mask"), cr = aovs.channel("refl.R");
  int n = 0, off = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (g.at(x, y, m) < 0.5f) continue;
      ++n;
      for (int c = 0; c < 3; ++c) off += std::abs(g.at(x, y, c) - aovs.at(x, y, cr + c)) > 1e-4f;
    }
  EXPECT_GT(n, 1000);
  EXPECT_LE(off, 3);
}

// The contract's composite built from the references reproduces the full reference: the
// area light has the point light's power and the effects are separable.
TEST(References, OracleCompositeMatchesBeauty) {
  Options o = small("contact", 96, 54);
  const Scene s = build_scene(o);
  const Image aovs = render_aovs(s, o);
  const Image soft = render_softshadow(s, o, 256), gloss = render_glossy(s, o, 256);
  const Image ref = render_beauty_ref(s, o, 256);
  const int cR = aovs.channel("R"), cd = aovs.channel("key.direct.R"),
            cs = aovs.channel("key.shadow"), cw = aovs.channel("refl.weight.R"),
            cr = aovs.channel("refl.R");
  double err = 0, hard = 0;
  int n = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double beauty = aovs.at(x, y, cR + c);
        const double comp = beauty +
                            aovs.at(x, y, cd + c) * (soft.at(x, y, 0) - aovs.at(x, y, cs)) +
                            aovs.at(x, y, cw + c) * (gloss.at(x, y, c) - aovs.at(x, y, cr + c));
        err += std::pow(comp - ref.at(x, y, c), 2);
        hard += std::pow(beauty - ref.at(x, y, c), 2);
        ++n;
      }
  err = std::sqrt(err / n);
  hard = std::sqrt(hard / n);
  std::printf("oracle composite RMSE %.5f, hard AOV beauty RMSE %.5f\n", err, hard);
  EXPECT_LT(err, 0.01);
  EXPECT_LT(err, 0.5 * hard) << "composite " << err << " vs hard " << hard;
}

TEST(Determinism, IndependentOfThreadCount) {
  Options o1 = small("stack", 64, 36), o2 = o1;
  o1.threads = 1;
  o2.threads = 2;
  o1.aov_spp = o2.aov_spp = 4;
  const Scene s = build_scene(o1);
  EXPECT_EQ(render_aovs(s, o1).pixels, render_aovs(s, o2).pixels);
  EXPECT_EQ(render_softshadow(s, o1, 16).pixels, render_softshadow(s, o2, 16).pixels);
  EXPECT_EQ(render_glossy(s, o1, 16).pixels, render_glossy(s, o2, 16).pixels);
  EXPECT_EQ(render_beauty_ref(s, o1, 16).pixels, render_beauty_ref(s, o2, 16).pixels);
  EXPECT_EQ(render_dof(s, o1, 16).pixels, render_dof(s, o2, 16).pixels);
}

TEST(Frames, ObjectMovesWithFrame) {
  Options o = small("contact", 64, 36);
  const Image f0 = render_aovs(build_scene(o), o);
  o.frame = 3;
  const Image f3 = render_aovs(build_scene(o), o);
  EXPECT_NE(f0.pixels, f3.pixels);
  o.frame = 0;
  EXPECT_EQ(render_aovs(build_scene(o), o).pixels, f0.pixels);
}

// Lit receivers find their own depth in the shadow map; umbra pixels find a closer one.
TEST(ShadowMap, AgreesWithHardShadows) {
  const Options o = small("contact");
  const Scene s = build_scene(o);
  const Image aovs = render_aovs(s, o);
  const Image map = render_shadowmap(s, 512);
  const auto m = world_to_light(s);
  const int cP = aovs.channel("P.X"), cs = aovs.channel("key.shadow"), cA = aovs.channel("A"),
            cd = aovs.channel("key.direct.R");
  int lit = 0, lit_ok = 0, umbra = 0, umbra_ok = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (aovs.at(x, y, cA) == 0 || aovs.at(x, y, cd) <= 0) continue;
      const double P[4] = {aovs.at(x, y, cP), aovs.at(x, y, cP + 1), aovs.at(x, y, cP + 2), 1};
      double q[3] = {0, 0, 0};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) q[r] += m[size_t(r * 4 + c)] * P[c];
      const double z = -q[2];
      const int u = int((q[0] / z + 1) * 0.5 * 512), v = int((1 - q[1] / z) * 0.5 * 512);
      if (z <= 0 || u < 0 || v < 0 || u >= 512 || v >= 512) continue;
      const double stored = map.at(u, v, 0);
      if (aovs.at(x, y, cs) == 1)
        ++lit, lit_ok += std::abs(stored - z) < 0.03 * z;
      else
        ++umbra, umbra_ok += stored < z * 0.97;
    }
  ASSERT_GT(lit, 1000);
  ASSERT_GT(umbra, 100);
  EXPECT_GT(lit_ok, 0.95 * lit);
  EXPECT_GT(umbra_ok, 0.95 * umbra);
}

TEST(Options, RejectedWithTheOptionNamed) {
  auto message = [](Options o) {
    try {
      validate(o);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Options o;
  o.width = 0;
  EXPECT_NE(message(o).find("--width"), std::string::npos);
  o = {};
  o.roughness = 1.5;
  EXPECT_NE(message(o).find("--roughness"), std::string::npos);
  o = {};
  o.scene = "nope";
  EXPECT_NE(message(o).find("nope"), std::string::npos);
  o = {};
  o.fstop = -1;
  EXPECT_NE(message(o).find("--fstop"), std::string::npos);
  o = {};
  o.sun_angle = 0;
  EXPECT_NE(message(o).find("--sun-angle"), std::string::npos);
  o.sun_angle = 91;
  EXPECT_NE(message(o).find("--sun-angle"), std::string::npos);
  EXPECT_EQ(message(Options{}), "");
  EXPECT_EQ(scene_names().size(), 12u);
}

}  // namespace

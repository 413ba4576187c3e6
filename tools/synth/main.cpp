// isg-synth: argument parsing and printing only; the work is in synth.h.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>

#include "synth.h"

int main(int argc, char** argv) {
  namespace synth = isg::synth;
  synth::Options o;
  std::string out;
  bool list = false;
  double light_radius = 0, sun_angle = 0, roughness = 0, fstop = 0;

  CLI::App app{"isg-synth: ground-truth AOVs and distribution-ray-traced references"};
  app.set_version_flag("--version", "isg-synth " ISG_VERSION);
  app.add_option("scene", o.scene, "scene name (see --list)");
  app.add_option("--out", out, "output folder");
  app.add_option("--width", o.width, "image width")->capture_default_str();
  app.add_option("--height", o.height, "image height")->capture_default_str();
  app.add_option("--aov-spp", o.aov_spp, "AOV samples per pixel (1: pixel centres)")
      ->capture_default_str();
  app.add_option("--ref-spp", o.ref_spp, "reference samples per pixel")->capture_default_str();
  auto* lr = app.add_option("--light-radius", light_radius,
                            "the first light's radius (world units; rect: half its width)");
  auto* sa = app.add_option("--sun-angle", sun_angle, "every sun's angle_deg (its disk, degrees)");
  auto* rough = app.add_option("--roughness", roughness, "roughness of every glossy surface");
  auto* fs = app.add_option("--fstop", fstop, "f-number; turns on DOF in ref/beauty.exr");
  app.add_option("--frame", o.frame, "frame number (moves the scene's moving object)")
      ->capture_default_str();
  app.add_option("--threads", o.threads, "worker threads (0: all cores)")->capture_default_str();
  app.add_option("--shadowmap-size", o.shadowmap_size, "shadow map size (square)")
      ->capture_default_str();
  bool no_refs = false;
  app.add_flag("--no-refs", no_refs, "skip ref/");
  app.add_flag("--list", list, "list the scenes and exit");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "isg-synth: error: %s\n", e.what());
    return 2;
  }
  if (list) {
    for (const auto& n : synth::scene_names())
      std::printf("%-16s %s\n", n.c_str(), synth::scene_description(n).c_str());
    return 0;
  }
  try {
    if (app.count("scene") == 0) throw std::runtime_error("scene: missing (see --list)");
    if (out.empty()) throw std::runtime_error("--out: missing");
    o.refs = !no_refs;
    if (lr->count()) o.light_radius = light_radius;
    if (sa->count()) o.sun_angle = sun_angle;
    if (rough->count()) o.roughness = roughness;
    if (fs->count()) o.fstop = fstop;
    synth::validate(o);
    for (const auto& t : synth::generate(o, out))
      std::printf("%-32s %8.2f s\n", t.file.c_str(), t.seconds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "isg-synth: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

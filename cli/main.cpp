// The `isg` executable: argument parsing and printing only; the work is in lib/.
#include <CLI/CLI.hpp>

#include <iostream>
#include <new>

#include "cli.h"
#include "farm.h"

using namespace isg::cli;

int main(int argc, char** argv) {
  CLI::App app{"isg: soft shadows, glossy reflections and depth of field from a renderer's AOVs"};
  app.set_version_flag("--version", version_text, "print the version, the commit and the Vulkan devices");
  app.require_subcommand(1);

  RunArgs ra;
  auto* run = app.add_subcommand("run", "process an AOV EXR and write the composite");
  run->add_option("input", ra.input, "input AOV EXR");
  run->add_option("-o,--output", ra.output, "output EXR");
  add_common(run, ra.common);
  run->add_option("--device", ra.device, "device index or name (see `isg devices`)");
  run->add_flag("--require-gpu", ra.require_gpu, "fail when only a CPU Vulkan device exists");
  run->add_flag("--timings", ra.timings, "print GPU time per pass and wall time per stage");
  run->add_flag("--dry-run", ra.dry_run, "print the plan (passes, resources) and stop");
  run->add_flag("--print-preset", ra.print_preset, "print every parameter's value as TOML and stop");
  run->add_option("--compression", ra.compression, "EXR compression (output.compression)");
  run->add_flag("--no-clobber", ra.no_clobber, "fail rather than replace an existing output");
  run->add_flag("--validation", ra.validation, "enable the Khronos validation layer");
  run->add_option("--preview", ra.preview,
                  "also write a display picture (.png/.jpg) of the composite through the "
                  "OpenColorIO view transform ($OCIO, or the built-in sRGB config)");
  run->add_option("--focus-view", ra.focus_view,
                  "also write a picture (.png/.jpg) of the focus plane: the composite in grey, in "
                  "focus green, nearer blue, farther orange (needs depth of field to run: dof.method)");
  run->add_option("--frames", ra.frames,
                  "frame range for a sequence: A-B, A-BxSTEP, or a list (input and -o hold #### or %04d)");
  run->add_flag("--skip-existing", ra.skip_existing, "sequence: leave frames whose output exists (resume)");
  run->add_flag("--keep-going", ra.keep_going,
                "sequence: report a bad frame and go on (exit 3 if any failed)");
  run->add_option("--input-colorspace", ra.input_colorspace,
                  "colour space of a beauty that is not scene-linear (an OpenColorIO name)");

  Common ic;
  std::string info_input;
  bool info_json = false;
  auto* info = app.add_subcommand("info", "roles found, channels, camera, which effects can run");
  info->add_option("input", info_input, "AOV EXR")->required();
  add_common(info, ic);
  info->add_flag("--json", info_json, "machine-readable output");

  std::string ca, cb, cmask;
  std::vector<std::string> cchan;
  bool cjson = false;
  auto* cmp = app.add_subcommand("compare", "error metrics of A against B, per channel");
  cmp->add_option("a", ca, "image")->required();
  cmp->add_option("b", cb, "reference")->required();
  cmp->add_option("--mask", cmask, "CHANNEL (in B, else A) or FILE:CHANNEL selecting the pixels to count");
  cmp->add_option("--channels", cchan, "channels to compare (default: all both have)")->delimiter(',');
  cmp->add_flag("--json", cjson, "machine-readable output");
  std::string cheat;
  double cheat_max = 0;
  cmp->add_option("--heatmap", cheat, "write an error heat-map picture (.png/.jpg)");
  cmp->add_option("--heatmap-max", cheat_max, "error shown as full scale (default: 99th percentile)");

  auto* devices = app.add_subcommand("devices", "list Vulkan devices");
  auto* presets = app.add_subcommand("presets", "list shipped presets");
  bool params_md = false;
  auto* params_cmd = app.add_subcommand("params", "list every parameter with its default, range and help");
  params_cmd->add_flag("--markdown", params_md, "as the Markdown table in docs/parameters.md");

  isg::roofline::Options rl;
  std::string rl_device;
  bool rl_json = false;
  auto* roofline = app.add_subcommand(
      "roofline", "time a plain cross-bilateral gather (the yardstick for the gather passes), in taps/s");
  roofline->add_option("--width", rl.width, "image width")->check(CLI::Range(1, 65536));
  roofline->add_option("--height", rl.height, "image height")->check(CLI::Range(1, 65536));
  roofline->add_option("--taps", rl.taps, "taps per pixel, odd squares (default 49,81)")->delimiter(',');
  roofline->add_option("--radius", rl.radii, "gather radii in pixels (default 4,8,16,32,64)")->delimiter(',');
  roofline->add_option("--repeats", rl.repeats, "timed dispatches per row after a warm-up; the best counts")
      ->check(CLI::Range(1, 1000));
  roofline->add_option("--device", rl_device, "device index or name (see `isg devices`)");
  roofline->add_flag("--json", rl_json, "one JSON object");

  isg::cli::FarmCommand farm(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Any bad command line exits 2 (docs/farm.md), whichever CLI11 error it was.
    return app.exit(e) == 0 ? 0 : kUsage;
  }
  try {
    if (*run) return cmd_run(ra);
    if (*info) return cmd_info(ic, info_input, info_json);
    if (*cmp) return cmd_compare(ca, cb, cmask, cchan, cjson, cheat, cheat_max);
    if (*devices) return cmd_devices();
    if (*presets) return cmd_presets();
    if (*params_cmd) return cmd_params(params_md);
    if (*roofline) return cmd_roofline(rl, rl_device, rl_json);
    if (farm.parsed()) return farm.run();
  } catch (const std::bad_alloc&) {
    std::cerr << "isg: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::string msg = e.what();
    auto nl = msg.find('\n');
    if (nl != std::string::npos) msg.resize(nl);
    std::cerr << "isg: error: " << msg << "\n";
    return 1;
  }
  return 0;
}

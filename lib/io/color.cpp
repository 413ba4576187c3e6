#include "io/color.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace OCIO = OCIO_NAMESPACE;

namespace isg::io {

namespace {

constexpr const char* kLinear = "Linear Rec.709 (sRGB)";
constexpr const char* kSrgb = "sRGB - Display";

OCIO::ConstConfigRcPtr builtin_config() {
  auto cfg = OCIO::Config::Create();
  cfg->setName("isg built-in");
  auto lin = OCIO::ColorSpace::Create();
  lin->setName(kLinear);
  lin->setFamily("Linear");
  lin->setEncoding("scene-linear");
  cfg->addColorSpace(lin);
  // sRGB: the piecewise curve, gamma 2.4 with a linear toe (IEC 61966-2-1). The forward
  // transform decodes; going from the linear reference to the display encodes, so inverse.
  auto srgb = OCIO::ColorSpace::Create();
  srgb->setName(kSrgb);
  srgb->setFamily("Display");
  srgb->setEncoding("sdr-video");
  auto curve = OCIO::ExponentWithLinearTransform::Create();
  curve->setGamma({2.4, 2.4, 2.4, 1.0});
  curve->setOffset({0.055, 0.055, 0.055, 0.0});
  curve->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  srgb->setTransform(curve, OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cfg->addColorSpace(srgb);
  cfg->setRole(OCIO::ROLE_SCENE_LINEAR, kLinear);
  cfg->setRole(OCIO::ROLE_DEFAULT, kLinear);
  cfg->addDisplayView("sRGB", "Standard", kSrgb, "");
  cfg->setActiveDisplays("sRGB");
  cfg->setActiveViews("Standard");
  cfg->validate();
  return cfg;
}

OCIO::ConstConfigRcPtr config() {
  try {
    if (const char* env = std::getenv("OCIO"); env && *env) return OCIO::Config::CreateFromEnv();
    return builtin_config();
  } catch (const OCIO::Exception& e) {
    throw IoError(std::string("OpenColorIO config ($OCIO): ") + e.what());
  }
}

std::vector<float> interleave(const Image& img, const std::vector<std::string>& rgb) {
  if (rgb.size() != 3) throw IoError("colour conversion needs three channels");
  std::vector<const Channel*> ch;
  for (const auto& n : rgb) {
    const Channel* c = img.find(n);
    if (!c) throw IoError(img.path.string() + ": no channel " + n);
    ch.push_back(c);
  }
  std::vector<float> px(3 * img.pixels());
  for (size_t i = 0; i < img.pixels(); ++i)
    for (int c = 0; c < 3; ++c) px[3 * i + c] = ch[c]->data[i];
  return px;
}

void apply(const OCIO::ConstProcessorRcPtr& proc, std::vector<float>& px, const Image& img) {
  OCIO::PackedImageDesc desc(px.data(), img.width, img.height, 3);
  proc->getDefaultCPUProcessor()->apply(desc);
}

}  // namespace

std::string color_config_description() {
  const char* env = std::getenv("OCIO");
  if (env && *env) return std::string("$OCIO = ") + env;
  return "built-in (linear Rec.709 scene-linear, sRGB display, Standard view)";
}

std::vector<std::string> color_spaces() {
  auto cfg = config();
  std::vector<std::string> out;
  out.reserve(size_t(cfg->getNumColorSpaces()));
  for (int i = 0; i < cfg->getNumColorSpaces(); ++i) out.emplace_back(cfg->getColorSpaceNameByIndex(i));
  return out;
}

void to_scene_linear(Image& img, const std::vector<std::string>& rgb, const std::string& colorspace) {
  auto cfg = config();
  if (!cfg->getColorSpace(colorspace.c_str())) {
    throw IoError("--input-colorspace " + colorspace + ": the OpenColorIO config (" +
                  color_config_description() + ") has no such colour space");
  }
  auto px = interleave(img, rgb);
  try {
    apply(cfg->getProcessor(colorspace.c_str(), OCIO::ROLE_SCENE_LINEAR), px, img);
  } catch (const OCIO::Exception& e) {
    throw IoError(std::string("--input-colorspace ") + colorspace + ": " + e.what());
  }
  for (int c = 0; c < 3; ++c) {
    Channel* ch = img.find(rgb[c]);
    for (size_t i = 0; i < img.pixels(); ++i) ch->data[i] = px[3 * i + c];
  }
}

std::vector<unsigned char> display_picture(const Image& img, const std::vector<std::string>& rgb,
                                           const ColorOptions& opt) {
  auto cfg = config();
  std::string display = opt.display.empty() ? cfg->getDefaultDisplay() : opt.display;
  std::string view = opt.view.empty() ? cfg->getDefaultView(display.c_str()) : opt.view;
  auto t = OCIO::DisplayViewTransform::Create();
  t->setSrc(OCIO::ROLE_SCENE_LINEAR);
  t->setDisplay(display.c_str());
  t->setView(view.c_str());
  auto px = interleave(img, rgb);
  try {
    apply(cfg->getProcessor(t), px, img);
  } catch (const OCIO::Exception& e) {
    throw IoError("preview: display " + display + ", view " + view + ": " + e.what());
  }
  std::vector<unsigned char> out(px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    float v = std::isfinite(px[i]) ? std::clamp(px[i], 0.0f, 1.0f) : 0.0f;
    out[i] = (unsigned char)std::lround(v * 255.0f);
  }
  return out;
}

}  // namespace isg::io

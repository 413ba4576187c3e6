// Colour management through OpenColorIO: EXR outputs stay scene-linear; previews go through a
// display/view transform; a beauty in another colour space is brought to scene-linear first.
#pragma once

#include <string>
#include <vector>

#include "io/image.h"

namespace isg::io {

struct ColorOptions {
  std::string display;  // empty: the config's default display
  std::string view;     // empty: the display's default view
};

// The config from $OCIO, or (OCIO 2.1 in Debian 12 has no built-in "ocio://default") an
// equivalent minimal one built in code: scene_linear = linear Rec.709, display "sRGB" with view
// "Standard" (the sRGB transfer function). Returns a one-line description of what was used.
std::string color_config_description();

// Names of the colour spaces the active config defines.
std::vector<std::string> color_spaces();

// Converts the named RGB channels of `img` (3 planes) in place from `colorspace` to scene-linear.
void to_scene_linear(Image& img, const std::vector<std::string>& rgb, const std::string& colorspace);

// 8-bit display picture of the RGB channels through the display/view transform.
std::vector<unsigned char> display_picture(const Image& img, const std::vector<std::string>& rgb,
                                           const ColorOptions& opt);

}  // namespace isg::io

// The focus view (issue 53): a picture of where the focus plane lies, to set it quickly. The
// composite's display picture in grey, pixels in focus (|CoC| under half a pixel) tinted green,
// those in front of the focus plane (CoC < 0) blue and those behind it (CoC > 0) orange, the
// tint growing with the blur up to 8 pixels.
#pragma once

#include <vector>

namespace isg::effects {

// display: 8-bit RGB, 3 bytes a pixel (io::display_picture); coc: dof.coc, a value a pixel.
std::vector<unsigned char> focus_picture(const std::vector<unsigned char>& display, const std::vector<float>& coc);

}  // namespace isg::effects

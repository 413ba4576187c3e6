#include "effects/dof/focus_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace isg::effects {

std::vector<unsigned char> focus_picture(const std::vector<unsigned char>& display, const std::vector<float>& coc) {
  if (display.size() != 3 * coc.size()) throw std::invalid_argument("focus_picture: sizes differ");
  constexpr double kFocus[3] = {64, 255, 64}, kNear[3] = {64, 128, 255}, kFar[3] = {255, 128, 32};
  constexpr double kInFocus = 0.5, kFull = 8.0;  // pixels of CoC radius
  std::vector<unsigned char> out(display.size());
  for (size_t i = 0; i < coc.size(); ++i) {
    const unsigned char* d = &display[3 * i];
    const double grey = 0.2126 * d[0] + 0.7152 * d[1] + 0.0722 * d[2];
    const double c = coc[i], a = std::abs(c);
    const double* tint = a < kInFocus ? kFocus : c < 0 ? kNear : kFar;
    const double w = a < kInFocus ? 0.6 : 0.2 + 0.6 * std::min(1.0, a / kFull);
    for (int k = 0; k < 3; ++k) out[3 * i + size_t(k)] = (unsigned char)std::lround((1 - w) * grey + w * tint[k]);
  }
  return out;
}

}  // namespace isg::effects

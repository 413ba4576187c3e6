#include "frames/frames.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <stdexcept>

namespace isg::frames {

namespace fs = std::filesystem;

namespace {
const std::regex kHashes("#+");
const std::regex kPrintf("%0?([0-9]*)d");
}  // namespace

bool is_sequence_pattern(const std::string& path) {
  std::string name = fs::path(path).filename().string();
  return std::regex_search(name, kHashes) || std::regex_search(name, kPrintf);
}

std::string expand_pattern(const std::string& pattern, int frame) {
  std::smatch m;
  std::string out = pattern;
  auto pad = [&](int width) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%0*d", width, frame);
    return std::string(buf);
  };
  if (std::regex_search(pattern, m, kHashes)) {
    out = m.prefix().str() + pad(int(m.length(0))) + m.suffix().str();
  } else if (std::regex_search(pattern, m, kPrintf)) {
    int width = m[1].length() ? std::stoi(m[1].str()) : 0;
    out = m.prefix().str() + pad(width) + m.suffix().str();
  }
  return out;
}

std::vector<int> parse_frames(const std::string& spec) {
  std::vector<int> frames;
  static const std::regex item(R"(\s*(-?\d+)(?:\s*-\s*(-?\d+)(?:x(\d+))?)?\s*)");
  size_t start = 0;
  while (start <= spec.size()) {
    size_t comma = spec.find(',', start);
    std::string part = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    std::smatch m;
    if (!std::regex_match(part, m, item)) {
      throw std::invalid_argument("--frames " + spec + ": '" + part + "' is not N, A-B or A-BxS");
    }
    int a = std::stoi(m[1].str());
    int b = m[2].matched ? std::stoi(m[2].str()) : a;
    int step = m[3].matched ? std::stoi(m[3].str()) : 1;
    if (b < a || step < 1) throw std::invalid_argument("--frames " + spec + ": '" + part + "' is empty");
    if ((int64_t(b) - a) / step > 1000000) throw std::invalid_argument("--frames " + spec + ": too many frames");
    for (int f = a; f <= b; f += step) frames.push_back(f);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return frames;
}

}  // namespace isg::frames

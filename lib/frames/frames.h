// Frame sequences: the #### / %04d patterns of file names and the --frames syntax, for `isg run`
// and `isg farm` (issue 56: a library of its own, with no GPU, image or planner dependency).
#pragma once

#include <string>
#include <vector>

namespace isg::frames {

// Frame sequences: "####" (zero-padded to the number of #) or printf-style "%04d" / "%d".
bool is_sequence_pattern(const std::string& path);
std::string expand_pattern(const std::string& pattern, int frame);
// "1001-1100", "1001-1100x4" (every 4th), "1,5,9-12"; throws std::invalid_argument naming it.
std::vector<int> parse_frames(const std::string& spec);

}  // namespace isg::frames

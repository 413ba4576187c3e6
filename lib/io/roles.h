// Channel roles (AOV contract input 1): which channels of a file play which part.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace isg::io {

// A role's value is the sum of its terms; each term lists one channel per component.
// (Cycles' sharp reflection is GlossDir + GlossInd: two terms.)
struct RoleBinding {
  std::string role;
  std::vector<std::vector<std::string>> terms;
  std::string how;  // "contract name", "Blender Cycles (layer ViewLayer)", "--channel", "[channels]"
  size_t components() const { return terms.empty() ? 0 : terms.front().size(); }
};

struct RoleRequest {
  std::vector<std::string> light_names;              // from the scene file; empty: discover
  std::map<std::string, std::string> overrides;      // role -> NAME (--channel / [channels])
  std::map<std::string, std::string> override_how;   // role -> where the override came from
  std::string layer;                                 // --layer
};

struct Roles {
  std::map<std::string, RoleBinding> found;
  std::vector<std::string> lights;  // lights whose channels were looked for
  std::string layer;                // the Blender view layer used, if any
  bool has(const std::string& role) const { return found.count(role) != 0; }
  const RoleBinding* get(const std::string& role) const;
};

// The roles the contract defines, light-independent ones first.
const std::vector<std::string>& global_roles();
// Per-light role suffixes: "shadow", "occluder", "direct".
const std::vector<std::string>& light_role_suffixes();
bool is_known_role(const std::string& role, const std::vector<std::string>& lights);

// Resolves roles from channel names. Throws IoError naming `file` for an ambiguous layer or an
// override that names channels the file lacks.
Roles resolve_roles(const std::vector<std::string>& channels, const RoleRequest& req,
                    const std::string& file);

}  // namespace isg::io

namespace isg::io {
struct Image;
// The role's value as `planes` consecutive planes (terms summed; missing planes filled with
// `fill`, e.g. alpha 1 for an RGB beauty).
std::vector<float> gather_role(const Image& img, const RoleBinding& b, int planes, float fill = 1.0f);
// The same, written to `dst` (planes × pixels floats; e.g. a mapped GPU buffer).
void gather_role_into(const Image& img, const RoleBinding& b, int planes, float* dst, float fill = 1.0f);
}  // namespace isg::io

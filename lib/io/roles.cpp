#include "io/roles.h"

#include <algorithm>
#include <set>

#include "io/image.h"

namespace isg::io {

namespace {

struct RoleSpec {
  std::string role;
  std::vector<std::string> contract;                  // contract channel names
  std::vector<std::vector<std::string>> cycles;       // Cycles names after "<layer>."
  std::vector<std::string> suffixes;                  // component suffixes for prefix overrides
  bool alpha_optional = false;
};

const std::vector<RoleSpec>& specs() {
  static const std::vector<RoleSpec> s = {
      {"beauty", {"R", "G", "B", "A"}, {{"Combined.R", "Combined.G", "Combined.B", "Combined.A"}},
       {"R", "G", "B", "A"}, true},
      {"depth", {"Z"}, {{"Depth.Z"}}, {}},
      // A circle of confusion in pixels (dof.coc_source = channel): isg's own output name.
      {"coc", {"dof.coc"}, {}, {}},
      {"position", {"P.X", "P.Y", "P.Z"}, {{"Position.X", "Position.Y", "Position.Z"}}, {"X", "Y", "Z"}},
      {"normal", {"N.X", "N.Y", "N.Z"}, {{"Normal.X", "Normal.Y", "Normal.Z"}}, {"X", "Y", "Z"}},
      {"roughness", {"roughness"}, {{"roughness.X"}}, {}},
      {"refl", {"refl.R", "refl.G", "refl.B"},
       {{"GlossDir.R", "GlossDir.G", "GlossDir.B"}, {"GlossInd.R", "GlossInd.G", "GlossInd.B"}},
       {"R", "G", "B"}},
      {"refl.dist", {"refl.dist"}, {}, {}},
      {"refl.weight", {"refl.weight.R", "refl.weight.G", "refl.weight.B"},
       {{"GlossCol.R", "GlossCol.G", "GlossCol.B"}}, {"R", "G", "B"}},
  };
  return s;
}

RoleSpec light_spec(const std::string& light, const std::string& suffix) {
  std::string r = light + "." + suffix;
  if (suffix == "direct") return {r, {r + ".R", r + ".G", r + ".B"}, {}, {"R", "G", "B"}};
  return {r, {r}, {}, {}};
}

bool all_in(const std::set<std::string>& have, const std::vector<std::string>& names) {
  return std::all_of(names.begin(), names.end(), [&](const auto& n) { return have.count(n) != 0; });
}

// Blender view layers: the prefix before ".Combined.R", ".Depth.Z", ... in channel names.
std::vector<std::string> find_layers(const std::vector<std::string>& channels) {
  std::set<std::string> layers;
  for (const auto& spec : specs()) {
    for (const auto& term : spec.cycles) {
      const std::string tail = "." + term.front();
      for (const auto& c : channels) {
        if (c.size() > tail.size() && c.compare(c.size() - tail.size(), tail.size(), tail) == 0) {
          layers.insert(c.substr(0, c.size() - tail.size()));
        }
      }
    }
  }
  return {layers.begin(), layers.end()};
}

}  // namespace

const RoleBinding* Roles::get(const std::string& role) const {
  auto it = found.find(role);
  return it == found.end() ? nullptr : &it->second;
}

const std::vector<std::string>& global_roles() {
  static const std::vector<std::string> r = [] {
    std::vector<std::string> v;
    for (const auto& s : specs()) v.push_back(s.role);
    return v;
  }();
  return r;
}

const std::vector<std::string>& light_role_suffixes() {
  static const std::vector<std::string> s = {"shadow", "occluder", "direct"};
  return s;
}

bool is_known_role(const std::string& role, const std::vector<std::string>& lights) {
  if (std::find(global_roles().begin(), global_roles().end(), role) != global_roles().end()) return true;
  for (const auto& l : lights)
    for (const auto& s : light_role_suffixes())
      if (role == l + "." + s) return true;
  return false;
}

Roles resolve_roles(const std::vector<std::string>& channels, const RoleRequest& req,
                    const std::string& file) {
  std::set<std::string> have(channels.begin(), channels.end());
  Roles out;

  // Lights: the scene file's, or discovered from "<L>.shadow" / "<L>.occluder" channels.
  out.lights = req.light_names;
  if (out.lights.empty()) {
    std::set<std::string> found;
    for (const auto& c : channels) {
      for (const std::string& tail : {std::string(".shadow"), std::string(".occluder")}) {
        if (c.size() > tail.size() && c.compare(c.size() - tail.size(), tail.size(), tail) == 0) {
          std::string l = c.substr(0, c.size() - tail.size());
          if (l.find('.') == std::string::npos) found.insert(l);
        }
      }
    }
    out.lights.assign(found.begin(), found.end());
  }

  std::vector<RoleSpec> all = specs();
  for (const auto& l : out.lights)
    for (const auto& s : light_role_suffixes()) all.push_back(light_spec(l, s));

  // View layer.
  auto layers = find_layers(channels);
  if (!req.layer.empty()) {
    if (std::find(layers.begin(), layers.end(), req.layer) == layers.end()) {
      std::string list;
      for (const auto& l : layers) list += (list.empty() ? "" : ", ") + l;
      throw IoError(file + ": --layer " + req.layer + ": no such view layer" +
                    (layers.empty() ? std::string(" (the file has none)") : " (found: " + list + ")"));
    }
    out.layer = req.layer;
  } else if (layers.size() == 1) {
    out.layer = layers.front();
  } else if (layers.size() > 1) {
    std::string list;
    for (const auto& l : layers) list += (list.empty() ? "" : ", ") + l;
    throw IoError(file + ": has several view layers (" + list + "): choose one with --layer NAME");
  }

  for (const auto& spec : all) {
    RoleBinding b;
    b.role = spec.role;
    auto ov = req.overrides.find(spec.role);
    if (ov != req.overrides.end()) {
      // NAME: an exact channel, a prefix completed with the role's component suffixes, or a
      // comma-separated list of channels.
      const std::string& name = ov->second;
      std::vector<std::string> names;
      if (name.find(',') != std::string::npos) {
        size_t p = 0;
        while (p <= name.size()) {
          size_t q = name.find(',', p);
          if (q == std::string::npos) q = name.size();
          names.push_back(name.substr(p, q - p));
          p = q + 1;
        }
      } else if (spec.contract.size() == 1) {
        names = {name};
      } else {
        for (const auto& sfx : spec.suffixes) names.push_back(name + "." + sfx);
        if (spec.alpha_optional && !have.count(names.back())) names.pop_back();
      }
      size_t need = spec.contract.size() - (spec.alpha_optional ? 1 : 0);
      if (names.size() < need || names.size() > spec.contract.size()) {
        throw IoError(file + ": " + ov->first + "=" + name + ": role " + spec.role + " needs " +
                      std::to_string(spec.contract.size()) + " channels");
      }
      for (const auto& n : names) {
        if (!have.count(n)) {
          throw IoError(file + ": " + ov->first + "=" + name + ": no channel " + n + " in the file");
        }
      }
      b.terms = {names};
      auto how = req.override_how.find(spec.role);
      b.how = how == req.override_how.end() ? "--channel" : how->second;
      out.found[spec.role] = b;
      continue;
    }
    std::vector<std::string> contract = spec.contract;
    if (spec.alpha_optional && !have.count(contract.back())) contract.pop_back();
    if (all_in(have, contract)) {
      b.terms = {contract};
      b.how = "contract name";
      out.found[spec.role] = b;
      continue;
    }
    if (!out.layer.empty() && !spec.cycles.empty()) {
      std::vector<std::vector<std::string>> terms;
      for (const auto& t : spec.cycles) {
        std::vector<std::string> full;
        full.reserve(t.size());
        for (const auto& n : t) full.push_back(out.layer + "." + n);
        if (spec.alpha_optional && !have.count(full.back())) full.pop_back();
        if (all_in(have, full)) terms.push_back(full);
      }
      if (terms.size() == spec.cycles.size()) {
        b.terms = terms;
        b.how = "Blender Cycles (layer " + out.layer + ")";
        out.found[spec.role] = b;
      }
    }
  }
  return out;
}

}  // namespace isg::io

namespace isg::io {
std::vector<float> gather_role(const Image& img, const RoleBinding& b, int planes, float fill) {
  std::vector<float> out(img.pixels() * size_t(planes));
  gather_role_into(img, b, planes, out.data(), fill);
  return out;
}

void gather_role_into(const Image& img, const RoleBinding& b, int planes, float* out, float fill) {
  const size_t n = img.pixels();
  for (int c = 0; c < planes; ++c) {
    float* dst = out + size_t(c) * n;
    if (size_t(c) >= b.components()) {
      std::fill(dst, dst + n, fill);
      continue;
    }
    // The sum of the terms from 0 (0 + x, not a copy: -0 becomes +0 as it always has), one
    // pass over dst for the usual single term.
    bool first = true;
    for (const auto& term : b.terms) {
      const Channel* ch = img.find(term[c]);
      if (!ch) throw IoError(img.path.string() + ": channel " + term[c] + " vanished");
      if (first) for (size_t i = 0; i < n; ++i) dst[i] = 0.0f + ch->data[i];
      else for (size_t i = 0; i < n; ++i) dst[i] += ch->data[i];
      first = false;
    }
    if (first) std::fill(dst, dst + n, 0.0f);
  }
}
}  // namespace isg::io

#include "params/params.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

namespace isg::params {

namespace fs = std::filesystem;

namespace {

std::string format_number(double d) {
  std::ostringstream s;
  s.precision(10);
  s << d;
  std::string t = s.str();
  if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
  return t;
}

std::string range_text(const Def& d) {
  if (d.type == Type::choice) {
    std::string s;
    for (const auto& c : d.choices) s += (s.empty() ? "" : " | ") + c;
    return s;
  }
  if (d.type == Type::boolean) return "true | false";
  std::ostringstream s;
  s << "[" << d.lo << ", " << d.hi << "]";
  return s.str();
}

std::string where_of(const fs::path& file, const toml::node& n) {
  return file.string() + ":" + std::to_string(n.source().begin.line);
}

}  // namespace

Params::Params(std::vector<Def> defs) : defs_(std::move(defs)) {
  std::set<std::string> seen;
  for (const auto& d : defs_) {
    if (!seen.insert(d.key).second) throw ParamError("parameter " + d.key + " declared twice");
    set_text(d.key, d.def, "default of " + d.key);
  }
}

const Def* Params::def(const std::string& key) const {
  for (const auto& d : defs_)
    if (d.key == key) return &d;
  return nullptr;
}

void Params::set(const std::string& key, const Value& v, const std::string& where) {
  const Def* d = def(key);
  if (!d) throw ParamError(where + ": unknown key " + key);
  auto bad = [&](const std::string& why) { throw ParamError(where + ": " + key + ": " + why); };
  switch (d->type) {
    case Type::boolean:
      if (!std::holds_alternative<bool>(v)) bad("must be true or false");
      break;
    case Type::integer: {
      if (!std::holds_alternative<long long>(v)) bad("must be an integer");
      long long i = std::get<long long>(v);
      if (i < d->lo || i > d->hi) bad("value " + std::to_string(i) + " is out of range " + range_text(*d));
      break;
    }
    case Type::number: {
      double x = std::holds_alternative<long long>(v) ? double(std::get<long long>(v))
                 : std::holds_alternative<double>(v)  ? std::get<double>(v)
                                                      : NAN;
      if (std::isnan(x) && !std::holds_alternative<double>(v)) bad("must be a number");
      if (!std::isfinite(x) || x < d->lo || x > d->hi) {
        bad("value " + format_number(x) + " is out of range " + range_text(*d));
      }
      values_[key] = x;
      return;
    }
    case Type::choice: {
      if (!std::holds_alternative<std::string>(v)) bad("must be one of " + range_text(*d));
      const auto& s = std::get<std::string>(v);
      if (std::find(d->choices.begin(), d->choices.end(), s) == d->choices.end()) {
        bad("'" + s + "' is not one of " + range_text(*d));
      }
      break;
    }
  }
  values_[key] = v;
}

void Params::set_text(const std::string& key, const std::string& text, const std::string& where) {
  const Def* d = def(key);
  if (!d) throw ParamError(where + ": unknown key " + key);
  auto bad = [&](const std::string& why) { throw ParamError(where + ": " + key + ": " + why); };
  switch (d->type) {
    case Type::boolean:
      if (text == "true" || text == "1" || text == "on") return set(key, true, where);
      if (text == "false" || text == "0" || text == "off") return set(key, false, where);
      bad("'" + text + "' is not true or false");
      break;
    case Type::integer: {
      long long i = 0;
      auto r = std::from_chars(text.data(), text.data() + text.size(), i);
      if (r.ec != std::errc() || r.ptr != text.data() + text.size()) bad("'" + text + "' is not an integer");
      return set(key, i, where);
    }
    case Type::number: {
      double x = 0;
      auto r = std::from_chars(text.data(), text.data() + text.size(), x);
      if (r.ec != std::errc() || r.ptr != text.data() + text.size()) bad("'" + text + "' is not a number");
      return set(key, x, where);
    }
    case Type::choice: return set(key, text, where);
  }
}

Def def(Flag k, const char* deflt, std::string help, std::string unit) {
  return {k.name, Type::boolean, deflt, 0, 0, {}, std::move(help), std::move(unit)};
}
Def def(Int k, const char* deflt, double lo, double hi, std::string help, std::string unit) {
  return {k.name, Type::integer, deflt, lo, hi, {}, std::move(help), std::move(unit)};
}
Def def(Number k, const char* deflt, double lo, double hi, std::string help, std::string unit) {
  return {k.name, Type::number, deflt, lo, hi, {}, std::move(help), std::move(unit)};
}
Def def(Choice k, const char* deflt, std::vector<std::string> choices, std::string help,
        std::string unit) {
  return {k.name, Type::choice, deflt, 0, 0, std::move(choices), std::move(help), std::move(unit)};
}

// Every read names the key it failed on: an unknown key, or one read as another type.
const Value& Params::value(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw ParamError("parameter " + key + ": unknown key (not in any table)");
  return it->second;
}

namespace {
template <class T>
const T& as(const Value& v, const std::string& key, const char* type) {
  if (const T* x = std::get_if<T>(&v)) return *x;
  throw ParamError("parameter " + key + ": read as " + type + " but declared otherwise");
}
}  // namespace

bool Params::flag(const std::string& key) const { return as<bool>(value(key), key, "a flag"); }
long long Params::integer(const std::string& key) const {
  return as<long long>(value(key), key, "an integer");
}
double Params::number(const std::string& key) const { return as<double>(value(key), key, "a number"); }
const std::string& Params::choice(const std::string& key) const {
  return as<std::string>(value(key), key, "a choice");
}

std::string Params::text(const std::string& key) const {
  const Value& v = value(key);
  if (auto b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (auto i = std::get_if<long long>(&v)) return std::to_string(*i);
  if (auto x = std::get_if<double>(&v)) return format_number(*x);
  return std::get<std::string>(v);
}

void Params::set_channel(const std::string& role, const std::string& name, const std::string& where) {
  if (name.empty()) throw ParamError(where + ": channels." + role + ": empty channel name");
  channels_[role] = {name, where};
}

void Params::load_preset(const std::string& name_or_path, const std::vector<fs::path>& dirs) {
  fs::path p(name_or_path);
  if (name_or_path.find('/') == std::string::npos && p.extension() != ".toml") {
    bool found = false;
    for (const auto& d : dirs) {
      if (fs::exists(d / (name_or_path + ".toml"))) {
        p = d / (name_or_path + ".toml");
        found = true;
        break;
      }
    }
    if (!found) throw ParamError("--preset " + name_or_path + ": no such preset (see `isg presets`)");
  }
  load_file(p, dirs, 0);
  preset_ = name_or_path;
}

void Params::load_file(const fs::path& file, const std::vector<fs::path>& dirs, int depth) {
  if (depth > 16) throw ParamError(file.string() + ": preset inheritance is circular or too deep");
  std::error_code ec;
  if (!fs::exists(file, ec)) throw ParamError(file.string() + ": no such preset file");
  toml::table tbl;
  try {
    tbl = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    throw ParamError(file.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                     std::string(e.description()));
  }
  if (auto base = tbl.get("base")) {
    auto s = base->value<std::string>();
    if (!s) throw ParamError(where_of(file, *base) + ": base: must be a preset name");
    fs::path bp = fs::path(*s);
    if (bp.extension() != ".toml") {
      bool found = false;
      for (const auto& d : dirs) {
        if (fs::exists(d / (*s + ".toml"))) {
          bp = d / (*s + ".toml");
          found = true;
          break;
        }
      }
      if (!found && fs::exists(file.parent_path() / (*s + ".toml"))) {
        bp = file.parent_path() / (*s + ".toml");
        found = true;
      }
      if (!found) throw ParamError(where_of(file, *base) + ": base: no preset named " + *s);
    } else if (bp.is_relative()) {
      bp = file.parent_path() / bp;
    }
    load_file(bp, dirs, depth + 1);
  }
  for (auto&& [k, node] : tbl) {
    std::string key(k.str());
    if (key == "base" || key == "description") {
      if (!node.is_string()) throw ParamError(where_of(file, node) + ": " + key + ": must be a string");
      continue;
    }
    const toml::table* section = node.as_table();
    if (!section) throw ParamError(where_of(file, node) + ": unknown key " + key);
    for (auto&& [k2, v] : *section) {
      std::string full = key + "." + std::string(k2.str());
      std::string w = where_of(file, v);
      if (key == "channels") {
        auto s = v.value<std::string>();
        if (!v.is_string() || !s) throw ParamError(w + ": " + full + ": must be a channel name");
        set_channel(std::string(k2.str()), *s, w);
        continue;
      }
      if (!def(full)) throw ParamError(w + ": unknown key " + full);
      if (v.is_boolean()) set(full, *v.value<bool>(), w);
      else if (v.is_integer()) set(full, static_cast<long long>(*v.value<int64_t>()), w);
      else if (v.is_floating_point()) set(full, *v.value<double>(), w);
      else if (v.is_string()) set(full, *v.value<std::string>(), w);
      else throw ParamError(w + ": " + full + ": unsupported value type");
    }
  }
}

std::string Params::to_toml() const {
  std::ostringstream s;
  s << "# isg preset: " << preset_ << "\n";
  std::string section;
  for (const auto& d : defs_) {
    auto dot = d.key.find('.');
    std::string sec = d.key.substr(0, dot), name = d.key.substr(dot + 1);
    if (sec != section) {
      s << (section.empty() ? "" : "\n") << "[" << sec << "]\n";
      section = sec;
    }
    s << "# " << d.help << " (" << range_text(d) << (d.unit.empty() ? "" : ", " + d.unit)
      << "; default " << d.def << ")\n";
    s << name << " = ";
    if (d.type == Type::choice) s << "\"" << text(d.key) << "\"\n";
    else s << text(d.key) << "\n";
  }
  if (!channels_.empty()) {
    s << "\n[channels]\n";
    for (const auto& [role, e] : channels_) s << "\"" << role << "\" = \"" << e.name << "\"\n";
  }
  return s.str();
}

std::vector<PresetInfo> list_presets(const std::vector<fs::path>& dirs) {
  std::vector<PresetInfo> out;
  std::set<std::string> seen;
  for (const auto& d : dirs) {
    std::error_code ec;
    if (!fs::is_directory(d, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(d, ec))
      if (e.path().extension() == ".toml") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::string name = f.stem().string();
      if (!seen.insert(name).second) continue;
      PresetInfo p{name, "", f};
      try {
        auto t = toml::parse_file(f.string());
        p.description = t["description"].value_or(std::string());
      } catch (const toml::parse_error&) {
        p.description = "(does not parse)";
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace isg::params

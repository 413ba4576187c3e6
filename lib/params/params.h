// Parameters describe themselves once (key, default, range, help, unit); the CLI, the preset
// parser, --print-preset, provenance and the docs all read that one table.
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace isg::params {

struct ParamError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Type { boolean, integer, number, choice };

struct Def {
  std::string key;  // "section.name"
  Type type = Type::number;
  std::string def;  // default, as text
  double lo = 0, hi = 0;              // inclusive range for integer / number
  std::vector<std::string> choices;   // for choice
  std::string help;
  std::string unit;
};

using Value = std::variant<bool, long long, double, std::string>;

// A parameter's key with its type: declared once, next to its effect's table, and read through
// Params::get, so a key string is typed once and a value is read as the type it was declared.
template <class T>
struct Key {
  const char* name;  // "section.name"
};
using Flag = Key<bool>;
using Int = Key<long long>;
using Number = Key<double>;
using Choice = Key<std::string>;

// Table rows from typed keys (the type follows from the key).
Def def(Flag k, const char* deflt, std::string help, std::string unit = "");
Def def(Int k, const char* deflt, double lo, double hi, std::string help, std::string unit = "");
Def def(Number k, const char* deflt, double lo, double hi, std::string help,
        std::string unit = "");
Def def(Choice k, const char* deflt, std::vector<std::string> choices, std::string help,
        std::string unit = "");

// Where a [channels] entry came from, for errors that name file:line.
struct ChannelEntry {
  std::string name;
  std::string where;
};

class Params {
 public:
  explicit Params(std::vector<Def> defs);

  const std::vector<Def>& defs() const { return defs_; }
  const Def* def(const std::string& key) const;

  // Sets from text (`--set key=value`); `where` prefixes errors ("--set", "preset.toml:12").
  void set_text(const std::string& key, const std::string& text, const std::string& where);
  void set(const std::string& key, const Value& v, const std::string& where);

  // Typed reads; an unknown key throws ParamError naming it.
  bool get(Flag k) const { return flag(k.name); }
  long long get(Int k) const { return integer(k.name); }
  double get(Number k) const { return number(k.name); }
  const std::string& get(Choice k) const { return choice(k.name); }

  bool flag(const std::string& key) const;
  long long integer(const std::string& key) const;
  double number(const std::string& key) const;
  const std::string& choice(const std::string& key) const;
  std::string text(const std::string& key) const;  // any value, formatted

  // Loads a preset file or a shipped preset's name; `base = "name"` is loaded first.
  void load_preset(const std::string& name_or_path, const std::vector<std::filesystem::path>& dirs);

  const std::string& preset_name() const { return preset_; }
  const std::map<std::string, ChannelEntry>& channels() const { return channels_; }
  void set_channel(const std::string& role, const std::string& name, const std::string& where);

  // TOML of every value, with help, range and unit as comments.
  std::string to_toml() const;

 private:
  void load_file(const std::filesystem::path& file, const std::vector<std::filesystem::path>& dirs,
                 int depth);
  std::vector<Def> defs_;
  std::map<std::string, Value> values_;
  std::map<std::string, ChannelEntry> channels_;
  std::string preset_ = "(defaults)";
  const Value& value(const std::string& key) const;
};

// The shipped presets (name, description, path) found in `dirs`.
struct PresetInfo {
  std::string name, description;
  std::filesystem::path path;
};
std::vector<PresetInfo> list_presets(const std::vector<std::filesystem::path>& dirs);

}  // namespace isg::params

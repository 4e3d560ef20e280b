#pragma once
// Typed reading of a scene file's TOML tables (input/scene_file.hpp) through toml++: every table checks that
// it holds only the keys it knows, and every value read names its key path and line when it is missing or
// wrong
// ("scene: key 'materials.steel.E' (line 6): expected a number or three (N, S, T), got \"big\"").
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <toml++/toml.h>
#include <vector>

#include "gapfe/core/error.hpp"

namespace gapfe::detail {

/// A table of the scene file with the path of its keys ("materials.steel"), which checks that it holds only
/// the keys it knows and reads typed values with errors naming the key and its line.
class SceneTable {
 public:
  SceneTable(const toml::table& table, std::string path, std::initializer_list<const char*> known)
      : table_(table), path_(std::move(path)) {
    for (auto&& [key, node] : table) {
      const std::string name(key.str());
      if (std::find_if(known.begin(), known.end(), [&](const char* k) { return name == k; }) != known.end())
        continue;
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      throw InputError("scene: unknown key '" + key_path(name) + "' (line " + std::to_string(line(node)) +
                       "); " + (path_.empty() ? "the top level" : "[" + path_ + "]") + " knows " + list);
    }
  }

  const std::string& path() const { return path_; }
  const toml::node* get(const char* key) const { return table_.get(key); }
  bool has(const char* key) const { return get(key) != nullptr; }
  /// "key 'materials.steel.E' (line 12)"
  std::string where(const char* key) const {
    const toml::node* n = get(key);
    return "key '" + key_path(key) + "'" + (n ? " (line " + std::to_string(line(*n)) + ")" : "");
  }
  std::string where() const { return "[" + path_ + "] (line " + std::to_string(line(table_)) + ")"; }
  [[noreturn]] void fail(const char* key, const std::string& expected) const {
    throw InputError("scene: " + where(key) + ": expected " + expected + got(get(key)));
  }

  /// A required or defaulted number; `check` returns the expectation it fails ("" when fine).
  double number(const char* key, std::optional<double> fallback = {},
                const char* expected = "a number") const {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      throw InputError("scene: " + where() + " needs " + where(key) + ": " + expected);
    }
    const std::optional<double> v = as_number(*n);
    if (!v || !std::isfinite(*v)) fail(key, expected);
    return *v;
  }
  double positive(const char* key) const {
    const double v = number(key, std::nullopt, "a number > 0");
    if (!(v > 0)) fail(key, "a number > 0");
    return v;
  }
  /// A number or an array of `count` numbers (one number: every entry).
  std::vector<double> numbers(const char* key, std::size_t count, const char* expected) const {
    const toml::node* n = get(key);
    if (!n) throw InputError("scene: " + where() + " needs " + where(key) + ": " + expected);
    if (const auto v = as_number(*n); v && std::isfinite(*v)) return std::vector<double>(count, *v);
    const toml::array* a = n->as_array();
    if (!a || a->size() != count) fail(key, expected);
    std::vector<double> out;
    for (const toml::node& e : *a) {
      const auto v = as_number(e);
      if (!v || !std::isfinite(*v)) fail(key, expected);
      out.push_back(*v);
    }
    return out;
  }
  std::string text(const char* key, std::optional<std::string> fallback = {}) const {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      throw InputError("scene: " + where() + " needs " + where(key) + ": a string");
    }
    if (!n->is_string()) fail(key, "a string");
    return std::string(*n->value<std::string_view>());
  }
  /// A string or an array of strings, each non-empty.
  std::vector<std::string> names(const char* key,
                                 std::optional<std::vector<std::string>> fallback = {}) const {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      throw InputError("scene: " + where() + " needs " + where(key) + ": a group name or a list of them");
    }
    std::vector<std::string> out;
    if (n->is_string()) {
      out.emplace_back(*n->value<std::string_view>());
    } else if (const toml::array* a = n->as_array()) {
      for (const toml::node& e : *a) {
        if (!e.is_string()) fail(key, "a group name or a list of them");
        out.emplace_back(*e.value<std::string_view>());
      }
    } else {
      fail(key, "a group name or a list of them");
    }
    if (out.empty() || std::any_of(out.begin(), out.end(), [](const std::string& s) { return s.empty(); }))
      fail(key, "a group name or a list of them, none empty");
    return out;
  }
  /// A sub-table with its own known keys.
  std::optional<SceneTable> table(const char* key, std::initializer_list<const char*> known) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (!n->is_table()) fail(key, "a table");
    return SceneTable(*n->as_table(), key_path(key), known);
  }
  /// An array of tables ([[key]] blocks), each with its own known keys.
  std::vector<SceneTable> tables(const char* key, std::initializer_list<const char*> known) const {
    std::vector<SceneTable> out;
    const toml::node* n = get(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) fail(key, "[[" + key_path(key) + "]] tables");
    for (std::size_t k = 0; k < a->size(); ++k)
      out.emplace_back(*a->get(k)->as_table(), key_path(key) + "[" + std::to_string(k + 1) + "]", known);
    return out;
  }
  const toml::table& raw() const { return table_; }

  static int line(const toml::node& n) { return static_cast<int>(n.source().begin.line); }
  /// The line the table starts on.
  int line() const { return line(table_); }
  static std::optional<double> as_number(const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    if (const auto* f = n.as_floating_point()) return f->get();
    return std::nullopt;
  }

 private:
  std::string key_path(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }
  static std::string got(const toml::node* n) {
    if (!n) return "";
    std::ostringstream s;
    s << ", got ";
    if (n->is_string())
      s << "\"" << *n->value<std::string_view>() << "\"";
    else if (n->is_table())
      s << "a table";
    else if (n->is_array())
      s << "an array of " << n->as_array()->size();
    else if (const auto v = as_number(*n))
      s << *v;
    else
      s << n->type();
    return s.str();
  }

  const toml::table& table_;
  std::string path_;
};

}  // namespace gapfe::detail

#pragma once
// The scene tests' meshes (tests/data/scenes) by file name, read once: the mesh loader of the fuzzed scenes.
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "gapfe/core/error.hpp"

namespace gapfe::fuzz {

inline std::string scene_mesh(const std::string& name) {
  static const std::map<std::string, std::string> meshes = [] {
    std::map<std::string, std::string> m;
    for (const char* file : {"thick_tube.msh", "two_tubes.msh", "plastic_tube.msh"}) {
      std::ifstream in(std::filesystem::path(GAPFE_SOURCE_DIR) / "tests/data/scenes" / file);
      std::ostringstream s;
      s << in.rdbuf();
      m[file] = s.str();
    }
    return m;
  }();
  const auto it = meshes.find(name);
  if (it == meshes.end()) throw InputError("no mesh '" + name + "'");
  return it->second;
}

}  // namespace gapfe::fuzz

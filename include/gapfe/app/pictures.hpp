#pragma once
// The pictures a run or `gapfe plot` adds to the SVG files the writers draw: PNG copies (rsvg-convert) and
// the curve of two history.csv columns.
#include <algorithm>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <map>
#include <spawn.h>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "gapfe/app/command_line.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/input/deck_options.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/output/field_plot.hpp"

namespace gapfe::app {

/// PNG beside an SVG picture through rsvg-convert (Debian's librsvg2-bin) when it is installed: run directly
/// (no shell), its output discarded; false when it is not there or fails.
inline bool rasterize(const std::string& svg) {
  static const bool present = [] {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (std::size_t at = 0; at <= dirs.size();) {
      const std::size_t end = std::min(dirs.find(':', at), dirs.size());
      if (end > at && ::access((dirs.substr(at, end - at) + "/rsvg-convert").c_str(), X_OK) == 0) return true;
      at = end + 1;
    }
    return false;
  }();
  if (!present) return false;
  const std::string png = svg.substr(0, svg.size() - 4) + ".png";
  std::vector<std::string> words{"rsvg-convert", "--background-color=white", "-o", png, svg};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid         = 0;
  const int spawned = posix_spawnp(&pid, "rsvg-convert", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  return spawned == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Unit names from "L,F,S" (the deck option `units`, or plot --units); generic names when empty.
inline PlotUnits plot_units(const std::string& text) {
  if (text.empty()) return {};
  const auto names = unit_names(text);
  return {names[0], names[1], names[2]};
}

/// The columns of a CSV file by name (history.csv), every row read as numbers.
inline std::map<std::string, std::vector<double>> read_columns(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw InputError("there is no '" + path + "' (a run of more than one load step writes it)");
  std::istringstream in(read_input(path, "history"));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names{""};
  for (const char c : line) {
    if (c == ',')
      names.emplace_back();
    else
      names.back().push_back(c);
  }
  std::map<std::string, std::vector<double>> columns;
  for (int row = 2; std::getline(in, line); ++row) {
    std::size_t at = 0;
    for (const auto& name : names) {
      if (at > line.size())
        throw FileError(path + ", line " + std::to_string(row) + ": fewer values than the header's columns");
      const std::size_t end = std::min(line.find(',', at), line.size());
      char* stop            = nullptr;
      std::string word      = line.substr(at, end - at);
      word.erase(word.find_last_not_of(' ') + 1);  // a row's padding (output/output_file.hpp)
      const double v = std::strtod(word.c_str(), &stop);
      if (word.empty() || *stop != '\0')
        throw InputError(path + ", line " + std::to_string(row) + ", column " + name + ": '" + word +
                         "' is not a number");
      columns[name].push_back(v);
      at = end + 1;
    }
  }
  return columns;
}

/// curve_Y_X.svg in `dir`: history.csv's column `y` against column `x`; returns its path.
inline std::string draw_curve(const std::string& dir, const std::string& x, const std::string& y,
                              const std::string& title) {
  const auto columns = read_columns(dir + "/history.csv");
  for (const std::string* c : {&x, &y})
    if (!columns.count(*c)) {
      std::vector<std::string> names;
      std::string list;
      for (const auto& [name, values] : columns)
        names.push_back(name), list += (list.empty() ? "" : ", ") + name;
      throw InputError("history.csv has no column '" + *c + "'" + suggestion(*c, names) + " (it has " + list +
                       ")");
    }
  const std::string path = dir + "/curve_" + y + "_" + x + ".svg";
  write_curve_svg(path, columns.at(x), columns.at(y), x, y, title);
  return path;
}

}  // namespace gapfe::app

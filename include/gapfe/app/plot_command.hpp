#pragma once
// `gapfe plot DIR`: pictures of a finished run, a field of one step (result.pvd's VTU files, read back) or a
// curve of history.csv.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "gapfe/app/command.hpp"
#include "gapfe/app/command_line.hpp"
#include "gapfe/app/pictures.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/input/vtu_reader.hpp"
#include "gapfe/output/field_plot.hpp"
#include "gapfe/output/run_folder.hpp"

namespace gapfe::app {

/// `gapfe plot DIR`: a field of one step (result.pvd's VTU files) or a curve of history.csv.
inline int plot(const Args& a, std::ostream& out, std::ostream& err) {
  std::ostringstream null_stream;
  std::ostream& log     = a.quiet ? null_stream : out;
  const std::string dir = a.deck;
  if (const std::string status = RunFolder::check(dir); status != "complete")
    err << "gapfe: note: the run in " << detail::visible_text(dir) << " did not complete (" << status
        << "): its files stop there\n";
  const PlotUnits units = plot_units(a.units);
  std::vector<std::string> written;
  if (!a.curve_x.empty()) {
    written.push_back(draw_curve(dir, a.curve_x, a.curve_y, std::filesystem::path(dir).filename().string()));
  } else {
    const std::string pvd = dir + "/result.pvd";
    if (!std::filesystem::exists(pvd))
      throw InputError("there is no '" + pvd + "' (a run with output_vtu = none writes no VTU files)");
    const auto datasets = read_pvd(read_input(pvd, "collection"), pvd);
    if (datasets.empty()) throw FileError(pvd + " lists no files");
    std::string file = datasets.back().second;
    if (a.step > 0) {
      char name[32];
      std::snprintf(name, sizeof name, "step_%04d", a.step);
      const auto it = std::find_if(datasets.begin(), datasets.end(), [&](const auto& d) {
        return d.second == name + std::string(".vtu") || d.second == name + std::string(".pvtu");
      });
      if (it == datasets.end()) {
        std::string steps;
        for (const auto& d : datasets)
          if (d.second.find("_split_") == std::string::npos) steps += (steps.empty() ? "" : ", ") + d.second;
        throw InputError("load step " + std::to_string(a.step) + " is not in " + pvd + " (it has " + steps +
                         ")");
      }
      file = it->second;
    }
    const auto listed = [&](const std::string& name, const std::string& by) {
      if (name.find('/') != std::string::npos || !RunFolder::run_file(name))
        throw FileError(by + " lists '" + name + "', which is not a file a run writes beside it");
      return dir + "/" + name;
    };
    const std::string source = listed(file, pvd);
    VtuData data;
    if (file.size() > 5 && file.substr(file.size() - 5) == ".pvtu") {  // a partitioned run's pieces, joined
      std::vector<VtuData> pieces;
      for (const std::string& piece : read_pvtu(read_input(source, "VTU file"), source)) {
        const std::string at = listed(piece, source);
        pieces.push_back(read_vtu(read_input(at, "VTU file"), at));
      }
      data = join_pieces(std::move(pieces), source);
    } else {
      data = read_vtu(read_input(source, "VTU file"), source);
    }
    const std::string stem = file.substr(0, file.rfind('.'));
    for (const std::string& field : a.plots.value_or(std::vector<std::string>{"mises"})) {
      const std::string path = dir + "/plot_" + field + (a.step > 0 ? "_" + stem : std::string()) + ".svg";
      write_field_svg(path, data, plot_field(data, field, units),
                      std::filesystem::path(dir).filename().string() + ", " + stem, units);
      written.push_back(path);
    }
  }
  for (const std::string& path : written) {
    const bool png = !a.no_png && rasterize(path);
    log << "wrote " << path << (png ? " and its .png" : "") << "\n";
  }
  return ok;
}

}  // namespace gapfe::app

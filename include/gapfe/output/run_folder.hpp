#pragma once
// One run per output folder. A run's files are a fixed family of names (run_file: the tables, gaps.csv,
// history.csv, plasticity.csv, estimates.csv, result.pvd and step_*.vtu, a partitioned run's step_*.pvtu
// and tables of its parts (nodes_pK.csv, elements_pK.csv, reactions_pK.csv), deformed.svg, the pictures
// plot_* and curve_*, and the temporaries of output/output_file.hpp), and a run starts by writing a manifest,
// gapfe-run.txt, which says the folder is a run's and how the run went (running; complete; stopped, and why:
// a run killed leaves "running"). Before a run writes anything:
//   - a folder with a manifest held the last run: every file of the family is removed (a link is removed,
//     never what it points to), so the new run's files are the only ones there, however few it writes;
//   - a folder with files of the family but no manifest holds results no gapfe run can vouch for (another
//     program's, or an older gapfe's): refused, unless the caller asks to overwrite them.
// Other files (the deck, `gapfe mesh`'s mesh_* files, the user's own) are never touched. `gapfe plot`
// reads only a folder with a manifest (and says when its run did not complete), and its pictures join
// the family (the next run removes them).
#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/text.hpp"
#include "gapfe/input/input_file.hpp"
#include "gapfe/output/output_file.hpp"

namespace gapfe {

struct RunFolder {
  static constexpr std::string_view kManifest = "gapfe-run.txt";

  /// Whether `name` (a file name, no folder) is one of the files a run or `gapfe plot` writes.
  static bool run_file(std::string_view name) {
    const auto starts = [&](std::string_view p) { return name.substr(0, p.size()) == p; };
    const auto ends   = [&](std::string_view s) {
      return name.size() >= s.size() && name.substr(name.size() - s.size()) == s;
    };
    for (const std::string_view fixed :
         {std::string_view("nodes.csv"), std::string_view("elements.csv"), std::string_view("reactions.csv"),
          std::string_view("gaps.csv"), std::string_view("history.csv"), std::string_view("plasticity.csv"),
          std::string_view("result.pvd"), std::string_view("deformed.svg"), std::string_view("estimates.csv"),
          kManifest})
      if (name == fixed) return true;
    for (const std::string_view table : {"nodes_p", "elements_p", "reactions_p"})  // a part's (K: digits)
      if (starts(table) && ends(".csv") && name.size() > table.size() + 4 &&
          std::all_of(name.begin() + static_cast<std::ptrdiff_t>(table.size()), name.end() - 4,
                      [](char c) { return c >= '0' && c <= '9'; }))
        return true;
    return (starts("step_") && (ends(".vtu") || ends(".pvtu"))) ||
           ((starts("plot_") || starts("curve_")) && (ends(".svg") || ends(".png"))) ||
           (starts(".") && name.size() > 13 && name.substr(name.size() - 13, 7) == ".gapfe-");
  }

  /// Make `dir` ready for a run described by `what` (see the top): FileError when it cannot be, or when it
  /// holds another program's results and `overwrite` is false.
  static void prepare(const std::string& dir, bool overwrite, const std::string& what) {
    try {
      make_ready(dir, overwrite, what);
    } catch (const std::filesystem::filesystem_error& e) {  // a check the folder's permissions refuse
      throw FileError("cannot make the output folder '" + dir + "' ready: " + e.path1().string() + ": " +
                      e.code().message());
    }
  }

 private:
  static void make_ready(const std::string& dir, bool overwrite, const std::string& what) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
      throw FileError("cannot make the output folder '" + dir +
                      "': " + (ec ? ec.message() : "it is not a folder"));
    const bool manifest = fs::exists(fs::path(dir) / kManifest);
    std::vector<fs::path> family;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
      if (run_file(e.path().filename().string()) && e.path().filename() != kManifest)
        family.push_back(e.path());
    if (ec) throw FileError("cannot read the output folder '" + dir + "': " + ec.message());
    std::sort(family.begin(), family.end());  // the message names the same files on every file system
    if (!manifest && !family.empty() && !overwrite) {
      std::string names;
      for (std::size_t k = 0; k < family.size() && k < 4; ++k)
        names += (k ? ", " : "") + family[k].filename().string();
      throw FileError("the output folder '" + dir + "' holds results that no gapfe run wrote there (" +
                      names + (family.size() > 4 ? ", ..." : "") +
                      "): choose another --out, remove them, or give --overwrite to replace them");
    }
    for (const fs::path& p : family)
      if (!fs::remove(p, ec) || ec)
        throw FileError("cannot remove the last run's " + p.string() + ": " + ec.message());
    record(dir, what, "running");
  }

 public:
  /// The run's outcome in the manifest: "complete", or "stopped: why" (a run killed leaves "running").
  static void record(const std::string& dir, const std::string& what, const std::string& status) {
    detail::write_file_atomically((std::filesystem::path(dir) / kManifest).string(),
                                  std::string(kHead) + detail::visible_text(what) + "\n" +
                                      std::string(kStatus) + detail::visible_text(status) + "\n");
  }

  /// A run stopped by an error `why`: recorded if the folder takes it. Never throws: the error that stopped
  /// the run is the one to report, not a second one from a full disk.
  static void record_stopped(const std::string& dir, const std::string& what,
                             const std::string& why) noexcept {
    try {
      record(dir, what, "stopped: " + why);
    } catch (...) {
    }
  }

  /// `gapfe plot`: the status of the run whose files `dir` holds (record()); FileError unless it holds a
  /// run's manifest.
  static std::string check(const std::string& dir) {
    const std::string path = (std::filesystem::path(dir) / kManifest).string();
    if (!std::filesystem::exists(path))
      throw FileError("'" + dir + "' holds no " + std::string(kManifest) +
                      ": it is not the output folder of a gapfe run (or of one older than the manifest)");
    const std::string text = read_input(path, "manifest");
    const std::size_t at   = text.find(kStatus);
    if (text.compare(0, kHead.size(), kHead) != 0 || at == std::string::npos)
      throw FileError(path + " is not a gapfe manifest (it should begin \"" + std::string(kHead) + "\")");
    const std::size_t from = at + kStatus.size();
    return text.substr(from, text.find('\n', from) - from);
  }

 private:
  static constexpr std::string_view kHead   = "gapfe: this folder holds the files of one run: ";
  static constexpr std::string_view kStatus = "status: ";
};

}  // namespace gapfe

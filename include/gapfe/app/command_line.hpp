#pragma once
// The `gapfe` command line: one table of commands and one of options, from which the parser and every
// --help text are made, so a new option is one row. Hand-written rather than CLI11 (Debian's libcli11-dev):
// this is shorter than the CLI11 set-up it would replace (the table is the whole specification), keeps the
// exit codes and messages the tests pin down, and suggests the nearest option for a misspelt one, which
// CLI11 does not. A deck option given here (--set, --element, ...) goes through ModelOptions::set, the typed
// setter the deck's `$ key = value` lines use.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gapfe/core/choices.hpp"

namespace gapfe::app {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CommandSpec {
  const char* name;
  const char* operand;  ///< DECK or DIR
  const char* summary;
};

inline constexpr CommandSpec kCommands[] = {
    {"run", "DECK", "solve every load step; CSV tables, VTU/PVD files and pictures in --out DIR"},
    {"mesh", "DECK", "the mesh only: mesh.svg with node and element numbers, tables, mesh.vtu in --out DIR"},
    {"info", "DECK", "what the deck asks for and which compiled variant serves it"},
    {"plot", "DIR",
     "pictures of a finished run in DIR: a field on the deformed mesh (plot_FIELD.svg), or a "
     "history.csv column against another (curve_Y_X.svg); PNG too when rsvg-convert is installed"},
};

struct OptionSpec {
  const char* name;
  const char* value;     ///< the value's name; nullptr for a flag
  const char* commands;  ///< the commands that take it, space-separated
  const char* help;
};

inline constexpr OptionSpec kOptions[] = {
    {"--out", "DIR", "run mesh", "the output directory (created when missing)"},
    {"--variant", "saas|saga", "run mesh info",
     "force a model variant (default: the smallest the deck needs)"},
    {"--set", "KEY=VALUE", "run mesh info",
     "a deck option (docs/decks.md \"Deck options\": format, element, solver, contact, friction, units, "
     "...)"},
    {"--format", "F", "run mesh info", "shorthand for --set format=F"},
    {"--element", "E", "run mesh info", "shorthand for --set element=E (legacy, quad4, quad4bbar)"},
    {"--solver", "S", "run mesh info",
     "shorthand for --set solver=S (eigen, cholmod; petsc: PETSc, under mpirun -np N a run partitioned over "
     "N "
     "processes)"},
    {"-OPTION", "[VALUE]", "run",
     "with solver = petsc: a PETSc option (-ksp_type cg, -pc_type gamg, -pc_factor_mat_solver_type mumps, "
     "-log_view, ...)"},
    {"--contact", "C", "run mesh info", "shorthand for --set contact=C"},
    {"--plasticity", "P", "run mesh info",
     "shorthand for --set plasticity=P (return-mapping, the default; tangent, the seed's one-solve scheme "
     "for legacy results)"},
    {"--output", "all|last|none", "run mesh info",
     "shorthand for --set output=...: which increments the CSV tables and VTU files get"},
    {"--plot", "FIELD", "run",
     "the field plot_FIELD.svg shows for the last step (repeat for more; default mises; none: no picture)"},
    {"--png", nullptr, "run",
     "also rasterize the run's pictures to PNG (rsvg-convert, Debian's librsvg2-bin)"},
    {"--estimate", nullptr, "run",
     "error bars on the reactions, the largest displacement and the largest von Mises stress: the model "
     "solved again on its mesh at 1/2 (and 1/4) of the spacing, extrapolated; in the log and estimates.csv"},
    {"--accuracy", "TOL", "run",
     "refine the mesh, then the load steps, until every quantity --estimate reports has an estimated "
     "relative error of at most TOL (e.g. 1e-3); the files are the last run's"},
    {"--time-limit", "SECONDS", "run", "with --accuracy: the time it may take in all (default 3600)"},
    {"--threads", "N", "run",
     "threads for the cells' passes, the files (with N >= 2 each increment's are written while the next "
     "computes) and, from 40,000 equations, CHOLMOD's factorization in two "
     "halves (the same results on any N); OpenBLAS gets N only for a factorization of more than 250,000 "
     "equations that has no split, whose rounding changes with N (default 1)"},
    {"--overwrite", nullptr, "run",
     "replace results in --out that no gapfe run wrote there (without it such a folder is refused; a folder "
     "a "
     "run wrote is always replaced whole)"},
    {"--field", "FIELD", "plot",
     "the field to draw (repeat for more; default mises): u, u_r, u_z, u_t, s_rr, s_zz, s_tt, s_rz, s_rt, "
     "s_zt, mises, eqps, gap_state, contact_force, material, error_estimate"},
    {"--step", "K", "plot", "the load step to draw (default: the last one written)"},
    {"--x", "COLUMN", "plot", "with --y: draw history.csv's column Y against column X"},
    {"--y", "COLUMN", "plot", "with --x: the curve's vertical column"},
    {"--units", "L,F,S", "plot",
     "unit names for the labels, e.g. mm,N,MPa (a run takes the deck's units option)"},
    {"--no-png", nullptr, "plot", "SVG only, even when rsvg-convert is installed"},
    {"--quiet", nullptr, "run mesh info plot", "no log on standard output"},
    {"--help", nullptr, "run mesh info plot", "this help (also -h)"},
    {"--version", nullptr, "run mesh info plot", "the version"},
};

struct Args {
  std::string command, deck, out;        ///< deck: the operand (DECK, or DIR for plot)
  std::optional<VariantChoice> variant;  ///< --variant: forced kinematics
  std::vector<std::pair<std::string, std::string>> options;
  bool quiet = false, help = false, version = false, png = false, no_png = false, overwrite = false;
  bool estimate     = false;  ///< run --estimate: error bars from finer meshes (app/error_bars.hpp)
  double accuracy   = 0;      ///< run --accuracy TOL (app/accuracy.hpp); 0: none
  double time_limit = 0;      ///< run --time-limit [s]: what --accuracy may take; 0: its default
  int threads       = 1;
  std::optional<std::vector<std::string>> plots;  ///< --plot / --field; unset: the default
  int step = 0;                                   ///< plot --step (0: the last)
  std::string curve_x, curve_y, units;
  /// PETSc's options (single-dash words and their values, as given), for solver = petsc: the program hands
  /// them to PetscInitialize.
  std::vector<std::string> petsc_options;
};

/// A PETSc option's name: one dash, then a letter (-ksp_type), but not -h. A negative number is a value.
inline bool petsc_option(const std::string& s) {
  return s.size() > 2 && s[0] == '-' && s[1] != '-' && std::isalpha(static_cast<unsigned char>(s[1]));
}

/// Levenshtein distance, for suggestions.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0]               = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j]   = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// "; did you mean 'X'?" for the nearest of `names` within a third of the word's length, else "".
template <class Names>
std::string suggestion(std::string_view word, const Names& names) {
  std::string best;
  std::size_t distance = word.size() / 3 + 2;  // a transposition is 2 edits
  for (const auto& n : names)
    if (const std::size_t d = edit_distance(word, n); d < distance) distance = d, best = n;
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

inline bool takes(const OptionSpec& o, const std::string& command) {
  const std::string list = " " + std::string(o.commands) + " ";
  return list.find(" " + command + " ") != std::string::npos;
}

/// The help of one command (or of the whole program when `command` is empty), from the tables.
inline std::string help_text(const std::string& command) {
  std::string s;
  if (command.empty()) {
    s = "usage: gapfe COMMAND OPERAND [options]   (gapfe COMMAND --help: its options)\n";
    for (const CommandSpec& c : kCommands) {
      std::string head = std::string("  gapfe ") + c.name + " " + c.operand;
      if (std::string_view(c.name) == "run" || std::string_view(c.name) == "mesh") head += " --out DIR";
      s += head + std::string(head.size() < 32 ? 32 - head.size() : 1, ' ') + c.summary + "\n";
    }
    s += "DECK: a card deck (BRL-CR-670 Appendix A) or a scene file NAME.toml (docs/scenes.md \"Scene "
         "files\")\n"
         "gapfe --version: the version\n"
         "exit status: 0 done; 1 the input or the model is wrong; 2 a load step cannot be solved; 3 a file "
         "cannot be read or written, or memory ran out; 64 a bad command line\n"
         "environment (docs/process.md): GAPFE_OPENMP_INLINE=0 gives OpenMP regions their teams, "
         "GAPFE_KEEP_MEMORY=0 leaves malloc's thresholds alone, GAPFE_HUGE_PAGES=0 skips the re-execution "
         "with huge pages for large models, GAPFE_RANK_LISTENER=0 runs an MPI launch without the thread that "
         "ends it when one rank fails alone (docs/cluster.md)\n";
    return s;
  }
  for (const CommandSpec& c : kCommands)
    if (command == c.name)
      s = std::string("usage: gapfe ") + c.name + " " + c.operand +
          (command == "run" || command == "mesh" ? " --out DIR" : "") + " [options]\n" + c.summary +
          "\noptions:\n";
  for (const OptionSpec& o : kOptions) {
    if (!takes(o, command)) continue;
    std::string head = std::string("  ") + o.name + (o.value ? std::string(" ") + o.value : std::string());
    s += head + std::string(head.size() < 26 ? 26 - head.size() : 1, ' ') + o.help + "\n";
  }
  return s;
}

inline Args parse(const std::vector<std::string>& a) {
  Args r;
  if (a.empty()) throw UsageError("no command given");
  r.command = a[0];
  if (r.command == "--help" || r.command == "-h" || r.command == "help")
    return r.command.clear(), r.help = true, r;
  if (r.command == "--version") return r.command.clear(), r.version = true, r;
  std::vector<std::string> commands;
  for (const CommandSpec& c : kCommands) commands.emplace_back(c.name);
  if (std::find(commands.begin(), commands.end(), r.command) == commands.end())
    throw UsageError("unknown command '" + r.command + "'" + suggestion(r.command, commands));
  std::vector<std::string> names;
  for (const OptionSpec& o : kOptions) names.emplace_back(o.name);
  for (std::size_t k = 1; k < a.size(); ++k) {
    const std::string s = a[k] == "-h" ? "--help" : a[k];
    if (petsc_option(s) && std::find(names.begin(), names.end(), "-" + s) != names.end())
      throw UsageError("unknown option '" + s + "'; did you mean '-" + s + "'?");
    if (petsc_option(s)) {  // PETSc's, with its value when the next word is not an option
      if (r.command != "run")
        throw UsageError(s + ": PETSc options belong to gapfe run (with --solver petsc)");
      r.petsc_options.push_back(s);
      if (k + 1 < a.size() && !petsc_option(a[k + 1]) && a[k + 1].rfind("--", 0) != 0)
        r.petsc_options.push_back(a[++k]);
      continue;
    }
    if (s.empty() || s[0] != '-' || s == "-") {  // "-": standard input
      if (!r.deck.empty())
        throw UsageError("more than one " + std::string(r.command == "plot" ? "directory" : "deck") +
                         " given ('" + r.deck + "', '" + s + "')");
      r.deck = s;
      continue;
    }
    const auto spec = std::find_if(std::begin(kOptions), std::end(kOptions),
                                   [&](const OptionSpec& o) { return s == o.name; });
    if (spec == std::end(kOptions)) throw UsageError("unknown option '" + s + "'" + suggestion(s, names));
    if (!takes(*spec, r.command))
      throw UsageError(s + " is not an option of gapfe " + r.command + " (it belongs to: " + spec->commands +
                       ")");
    std::string value;
    if (spec->value) {
      if (k + 1 >= a.size()) throw UsageError(s + " needs a value (" + spec->value + ")");
      value = a[++k];
    }
    if (s == "--out") {
      r.out = value;
    } else if (s == "--variant") {
      r.variant = choice_named<VariantChoice>(value);
      if (!r.variant) throw UsageError("--variant: '" + value + "' is not a compiled variant (saas, saga)");
    } else if (s == "--set") {
      const auto eq = value.find('=');
      if (eq == std::string::npos) throw UsageError("--set needs KEY=VALUE, got '" + value + "'");
      r.options.emplace_back(value.substr(0, eq), value.substr(eq + 1));
    } else if (s == "--format" || s == "--element" || s == "--solver" || s == "--contact" ||
               s == "--plasticity" || s == "--output") {
      r.options.emplace_back(s.substr(2), value);
    } else if (s == "--threads" || s == "--step") {
      std::size_t used = 0;
      int count        = 0;
      try {
        count = std::stoi(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      const int most = s == "--threads" ? 1024 : 1'000'000;
      if (used != value.size() || count < 1 || count > most)
        throw UsageError(s + ": '" + value + "' is not " +
                         (s == "--threads" ? "a thread count" : std::string("a load step")) +
                         " (a whole number from 1 to " + std::to_string(most) + ")");
      (s == "--threads" ? r.threads : r.step) = count;
    } else if (s == "--accuracy" || s == "--time-limit") {
      std::size_t used = 0;
      double number    = 0;
      try {
        number = std::stod(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      const bool fine = used == value.size() && std::isfinite(number) &&
                        (s == "--accuracy" ? number > 0 && number < 1 : number > 0);
      if (!fine)
        throw UsageError(s + ": '" + value + "' is not " +
                         (s == "--accuracy" ? "a relative error between 0 and 1 (1e-3: 0.1%)"
                                            : "a time in seconds (a number > 0)"));
      (s == "--accuracy" ? r.accuracy : r.time_limit) = number;
    } else if (s == "--plot" || s == "--field") {
      if (!r.plots) r.plots.emplace();
      if (value != "none") r.plots->push_back(value);
    } else if (s == "--x" || s == "--y") {
      (s == "--x" ? r.curve_x : r.curve_y) = value;
    } else if (s == "--units") {
      r.units = value;
    } else {
      (s == "--quiet"       ? r.quiet
       : s == "--help"      ? r.help
       : s == "--version"   ? r.version
       : s == "--png"       ? r.png
       : s == "--overwrite" ? r.overwrite
       : s == "--estimate"  ? r.estimate
                            : r.no_png) = true;
    }
  }
  if (r.help || r.version) return r;
  if (r.deck.empty()) throw UsageError(r.command == "plot" ? "no run directory given" : "no deck given");
  if ((r.command == "run" || r.command == "mesh") && r.out.empty())
    throw UsageError(r.command + " needs --out DIR");
  if (r.estimate && r.accuracy > 0)
    throw UsageError("--estimate and --accuracy: give one (--accuracy reports the error bars too)");
  if (r.time_limit > 0 && r.accuracy == 0)
    throw UsageError("--time-limit goes with --accuracy (the time its ladder of runs may take)");
  if (r.curve_x.empty() != r.curve_y.empty())
    throw UsageError("--x and --y go together (the curve's two columns)");
  return r;
}

}  // namespace gapfe::app

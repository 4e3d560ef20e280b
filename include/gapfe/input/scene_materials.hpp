#pragma once
// A scene file's [materials.NAME] tables as the deck's material cards (Data 10-11): elastic constants,
// isotropic or orthotropic, one row or a temperature table, and the yield card (input/scene_file.hpp).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "gapfe/input/model_description.hpp"
#include "gapfe/input/scene_table.hpp"

namespace gapfe::detail {

/// One elastic row from a table holding E, nu and optionally G and alpha, each one number (isotropic) or
/// three (N, S, T).
inline ElasticConstants scene_elastic_row(const SceneTable& t, double temperature) {
  const char* three = "a number or three (N, S, T)";
  const auto E      = t.numbers("E", 3, three);
  const auto nu     = t.numbers("nu", 3, three);
  ElasticConstants c;
  c.temperature = temperature;
  c.E_N = E[0], c.E_S = E[1], c.E_T = E[2];
  c.nu_NS = nu[0], c.nu_NT = nu[1], c.nu_ST = nu[2];
  if (t.has("G")) {
    const auto G = t.numbers("G", 3, three);
    c.G_NS = G[0], c.G_ST = G[1], c.G_TN = G[2];
  } else if (E[0] == E[1] && E[1] == E[2] && nu[0] == nu[1] && nu[1] == nu[2]) {
    c.G_NS = c.G_ST = c.G_TN = ElasticConstants::isotropic(E[0], nu[0]).G_NS;
  } else {
    throw InputError("scene: " + t.where() + " needs " + t.where("G") +
                     ": an orthotropic material (three E or nu) gives its shear moduli");
  }
  if (t.has("alpha")) {
    const auto a = t.numbers("alpha", 3, three);
    c.alpha_N = a[0], c.alpha_S = a[1], c.alpha_T = a[2];
  }
  try {
    c.validate("");
  } catch (const InputError& e) {
    throw InputError("scene: " + t.where() + e.what());
  }
  return c;
}

/// [materials.NAME]: the deck material (its table and yield card) and its surfaces and orientation.
struct SceneMaterial {
  std::string name;
  MaterialInput input;
  std::vector<std::string> surfaces;
  double beta_deg = 0, helix_deg = 0;
  bool has_number = false;
};

inline SceneMaterial scene_material(const std::string& name, const SceneTable& t) {
  SceneMaterial m;
  m.name     = name;
  m.surfaces = t.names("surfaces", std::vector<std::string>{name});
  if (t.has("number")) {
    const double k = t.number("number");
    if (!(k >= 1 && k <= 1e6 && k == std::floor(k))) t.fail("number", "a whole number from 1 to 1000000");
    m.input.id = static_cast<int>(k), m.has_number = true;
  }
  m.input.ref           = {"[materials." + name + "]", SceneTable::line(t.raw())};
  m.input.table.density = t.number("density", 0.0);
  if (m.input.table.density < 0) t.fail("density", "a number >= 0");
  const std::string thermal = t.text("thermal", std::string("coefficients"));
  if (thermal != "coefficients" && thermal != "free-strain")
    t.fail("thermal", "\"coefficients\" or \"free-strain\"");
  m.input.table.thermal = thermal == "free-strain" ? ThermalInput::free_strain : ThermalInput::coefficients;
  m.beta_deg            = t.number("beta", 0.0);
  m.helix_deg           = t.number("helix", 0.0);
  if (t.has("rows")) {
    if (t.has("E") || t.has("nu") || t.has("G") || t.has("alpha"))
      throw InputError("scene: " + t.where() + ": give the constants either in [[" + t.path() +
                       ".rows]] (a temperature table) or directly, not both");
    for (const SceneTable& row : t.tables("rows", {"temperature", "E", "nu", "G", "alpha"})) {
      const double T = row.number("temperature");
      if (!m.input.table.rows.empty() && !(T > m.input.table.rows.back().temperature))
        row.fail("temperature", "a temperature above the row before's (rows in increasing temperature)");
      m.input.table.rows.push_back(scene_elastic_row(row, T));
    }
  } else {
    m.input.table.rows.push_back(scene_elastic_row(t, 0.0));
  }
  if (t.has("yield") || t.has("hardening")) {
    YieldCard card;
    if (const toml::node* y = t.get("yield"); y && SceneTable::as_number(*y)) {
      const double Y = t.positive("yield");  // Mises: shear yield Y / sqrt(3)
      card.yield     = {Y, Y, Y, Y / std::sqrt(3.0), Y / std::sqrt(3.0), Y / std::sqrt(3.0)};
    } else {
      const auto v = t.numbers("yield", 6, "one yield stress (Mises) or six [N, S, T, NS, NT, TS], all > 0");
      for (int k = 0; k < 6; ++k) {
        if (!(v[k] > 0)) t.fail("yield", "one yield stress (Mises) or six [N, S, T, NS, NT, TS], all > 0");
        card.yield[k] = v[k];
      }
    }
    card.hardening = t.number("hardening", 0.0);
    card.blank     = false;
    m.input.yield  = card;
  } else {
    m.input.yield = YieldCard{};  // blank: elastic (a scene is read in a format with yield cards)
  }
  return m;
}

}  // namespace gapfe::detail

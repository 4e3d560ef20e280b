#pragma once
// The seed's card deck (BRL-CR-670 Appendix A, cards 0-15) as data: the model it describes (a
// ModelDescription, input/model_description.hpp) and the cards only a deck has, which describe its I-J grid
// (Data 2-6) and its plot (Data 7-8). input/deck_reader.hpp fills it; input/deck_scene.hpp builds its mesh.
#include <array>
#include <string>
#include <vector>

#include "gapfe/input/model_description.hpp"
#include "gapfe/mesh/ij_grid.hpp"

namespace gapfe {

struct ControlCard {  // Data 2
  int nnla = 0, numtc = 0, nummat = 0, numpc = 0, numsc = 0, numst = 0;
  double tref = 0;
  int inert = 0, nlinc = 0, inci = 0, incf = 0, iplot = 0;
};

struct MeshControlCard {  // Data 3
  int max_i = 0, max_j = 0, nseg = 0, nbc = 0, nmtl = 0;
};

struct BoundaryCard {  // Data 5: nodes in [i1, i2] x [j1, j2]
  int i1 = 0, i2 = 0, j1 = 0, j2 = 0, code = 0;
  std::array<double, 3> value{};  ///< XR, XZ, XT
  CardRef ref;
};

struct MaterialBlockCard {  // Data 6: cells whose four corners lie in [i1, i2] x [j1, j2]
  int material = 0, i1 = 0, i2 = 0, j1 = 0, j2 = 0;
  double beta_deg = 0, alpha_deg = 0;
  int iang = 0, nang = 0, ijdir = 0;
  CardRef ref;
};

/// A card deck as read: the model it describes, and the cards of its grid, which build_scene
/// (input/deck_scene.hpp) turns into the mesh. Everything after reading takes the ModelDescription.
struct Deck : ModelDescription {
  ControlCard control;
  MeshControlCard mesh;
  std::vector<Segment> segments;
  std::vector<CardRef> segment_refs;
  std::vector<BoundaryCard> boundary;
  std::vector<MaterialBlockCard> blocks;
  std::string plot_title;
  double plot_rmax = 0, plot_zmax = 0;
  /// A refined deck's (input/deck_refine.hpp): the finer grid's indices of the deck's own grid lines, I and
  /// J, ascending. Its BC cards' forces act at their crossings only, and IANG counts cells between them.
  /// Empty: every line is the deck's own.
  std::vector<int> own_i, own_j;
};

}  // namespace gapfe

#pragma once
// Named arrays of point and cell values, as VTU files hold them: what the VTU writer writes
// (output/vtu_writer.hpp) and the reader gives back (input/vtu_reader.hpp), and what the pictures draw.
#include <string>
#include <vector>

#include "gapfe/core/types.hpp"

namespace gapfe {

/// A point or cell array: `components` values per point or cell, row after row.
struct VtuField {
  std::string name;
  int components = 1;
  std::vector<double> values;
  bool integer = false;  ///< written as Int32 (material ids, status codes)
};

/// A VTU file's mesh and arrays: points (x, y) = (r, z), each cell's nodes, point and cell arrays.
struct VtuData {
  std::vector<Vec2> points;
  std::vector<std::vector<int>> cells;
  std::vector<VtuField> point_data, cell_data;

  const VtuField* point(const std::string& name) const { return find(point_data, name); }
  const VtuField* cell(const std::string& name) const { return find(cell_data, name); }

 private:
  static const VtuField* find(const std::vector<VtuField>& fields, const std::string& name) {
    for (const auto& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  }
};

}  // namespace gapfe

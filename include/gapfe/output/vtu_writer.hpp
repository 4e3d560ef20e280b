#pragma once
// VTK XML unstructured grid for ParaView: the meridian plane as x = r, y = z, and the PVD collection
// that strings one file per load step together. Arrays are VTK's inline binary format (base64 of a
// UInt32 byte count and the little-endian values): exact doubles, and several times faster to write
// than text, which matters when every contact increment writes a file.
//
// Files are written whole through write_file_atomically (output/output_file.hpp), so an interrupted run never
// leaves a half-written file under the final name.
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/mesh/mesh.hpp"
#include "gapfe/output/output_file.hpp"
#include "gapfe/problem/field_arrays.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe {

/// Cells as VTK wants them: VTK types 5 (triangle), 9 (quad), 22 (quadratic triangle), 23 (quad8).
struct VtuCells {
  std::vector<int> connectivity, offsets;
  std::vector<std::uint8_t> types;
  void add(const int* nodes, int count) {
    connectivity.insert(connectivity.end(), nodes, nodes + count);
    offsets.push_back(static_cast<int>(connectivity.size()));
    types.push_back(count == 3 ? 5 : count == 4 ? 9 : count == 6 ? 22 : 23);
  }
  std::size_t size() const { return types.size(); }
};

namespace detail {

/// VTK inline binary: base64 of [UInt32 byte count][the values' bytes], then a newline. Written in place
/// into `s` (resized once): at 1e6 nodes these arrays are 100 MB of text.
template <class T>
void append_binary(std::string& s, const std::vector<T>& values) {
  static_assert(std::endian::native == std::endian::little, "the VTU files declare LittleEndian");
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  if (values.size() * sizeof(T) > 0xffffffffu)  // the header's UInt32 would wrap: a file ParaView misreads
    throw FileError("a VTU array of " + std::to_string(values.size()) +
                    " values is past the 4 GiB that "
                    "its UInt32 header can count: write fewer steps' fields, or a coarser mesh");
  const auto bytes = static_cast<std::uint32_t>(values.size() * sizeof(T));
  unsigned char header[sizeof bytes];
  std::memcpy(header, &bytes, sizeof bytes);
  const auto* data    = reinterpret_cast<const unsigned char*>(values.data());
  const std::size_t n = sizeof bytes + bytes;  // the encoded stream: header, then data
  const auto at       = [&](std::size_t i) -> std::uint32_t {
    return i < sizeof bytes ? header[i] : data[i - sizeof bytes];
  };
  const std::size_t start = s.size();
  s.resize(start + 4 * ((n + 2) / 3) + 1);
  char* out         = s.data() + start;
  const auto encode = [&](std::uint32_t b) {
    out[0] = kDigits[b >> 18], out[1] = kDigits[(b >> 12) & 63], out[2] = kDigits[(b >> 6) & 63];
    out[3] = kDigits[b & 63], out += 4;
  };
  std::size_t k = 0;
  for (; k + 3 <= n && k < 2 * 3; k += 3) encode(at(k) << 16 | at(k + 1) << 8 | at(k + 2));  // the header
  // Past the header (k >= 4 whenever a whole group of data follows; an empty array stops at k = 3).
  for (const unsigned char* d = k >= sizeof bytes ? data + (k - sizeof bytes) : data; k + 3 <= n;
       k += 3, d += 3)
    encode(std::uint32_t(d[0]) << 16 | std::uint32_t(d[1]) << 8 | d[2]);
  if (const std::size_t rest = n - k; rest > 0) {
    const std::uint32_t b = at(k) << 16 | (rest > 1 ? at(k + 1) << 8 : 0u);
    encode(b);
    out[-2] = rest > 1 ? out[-2] : '=';
    out[-1] = '=';
  }
  *out = '\n';
}

inline void append_array(std::string& s, const VtuField& f) {
  s += "<DataArray type=\"";
  s += f.integer ? "Int32" : "Float64";
  s += "\" Name=\"" + f.name + "\" NumberOfComponents=\"" + std::to_string(f.components) +
       "\" format=\"binary\">\n";
  if (f.integer)
    append_binary(s, std::vector<std::int32_t>(f.values.begin(), f.values.end()));
  else
    append_binary(s, f.values);
  s += "</DataArray>\n";
}

}  // namespace detail

/// The mesh part of a VTU file (its <Points> and <Cells> sections, encoded), which a run's files share:
/// a series of files of one mesh encodes it once.
struct VtuMesh {
  std::size_t points = 0, cells = 0;
  std::string xml;

  VtuMesh(const std::vector<Vec2>& nodes, const VtuCells& c) : points(nodes.size()), cells(c.size()) {
    xml.reserve(
        (24 * nodes.size() + 4 * (c.connectivity.size() + c.offsets.size()) + c.types.size()) / 3 * 4 + 512);
    xml += "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">\n";
    std::vector<double> xyz;
    xyz.reserve(3 * nodes.size());
    for (const auto& x : nodes) xyz.insert(xyz.end(), {x(0), x(1), 0.0});
    detail::append_binary(xml, xyz);
    xml += "</DataArray></Points>\n<Cells>\n";
    const auto ints = [&](const char* name, const auto& v) {
      xml += std::string("<DataArray type=\"Int32\" Name=\"") + name + "\" format=\"binary\">\n";
      detail::append_binary(xml, std::vector<std::int32_t>(v.begin(), v.end()));
      xml += "</DataArray>\n";
    };
    ints("connectivity", c.connectivity);
    ints("offsets", c.offsets);
    xml += "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">\n";
    detail::append_binary(xml, c.types);
    xml += "</DataArray>\n</Cells>\n";
  }
};

/// Point and cell arrays on `mesh` to `path`; `cell_xml` is more cell arrays already encoded
/// (detail::append_array), for arrays a series of files repeats unchanged.
inline void write_vtu(const std::string& path, const VtuMesh& mesh, const std::vector<VtuField>& point_data,
                      const std::vector<VtuField>& cell_data, const std::string& cell_xml = {}) {
  std::size_t raw = 0;
  for (const auto* fields : {&point_data, &cell_data})
    for (const auto& f : *fields) raw += f.values.size() * (f.integer ? 4 : 8);
  std::string s;
  s.reserve(mesh.xml.size() + cell_xml.size() + raw / 3 * 4 + 4096);  // base64: 3 bytes to 4 characters
  s += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n";
  s += "<UnstructuredGrid><Piece NumberOfPoints=\"" + std::to_string(mesh.points) + "\" NumberOfCells=\"" +
       std::to_string(mesh.cells) + "\">\n";
  s += mesh.xml;
  s += "<PointData>\n";
  for (const auto& f : point_data) detail::append_array(s, f);
  s += "</PointData>\n<CellData>\n";
  for (const auto& f : cell_data) detail::append_array(s, f);
  s += cell_xml;
  s += "</CellData>\n</Piece></UnstructuredGrid></VTKFile>\n";
  detail::write_file_atomically(path, s);
}

/// Write nodes (r, z), cells and point / cell arrays to `path`.
inline void write_vtu(const std::string& path, const std::vector<Vec2>& nodes, const VtuCells& cells,
                      const std::vector<VtuField>& point_data, const std::vector<VtuField>& cell_data) {
  write_vtu(path, VtuMesh(nodes, cells), point_data, cell_data);
}

/// An analysis' results on its mesh: displacement and reaction per node (`s`); centroid stress and strain
/// (`centroids`, one per cell, cells then triangles, as a driver's centroid_values() gives them; global
/// Voigt order [rr, zz, hoop, rz, z-theta, theta-r]) and material number (1-based) per cell.
template <int NodesPerCell>
void write_vtu(const std::string& path, const Mesh<NodesPerCell>& m, const Solution& s,
               const std::vector<PointValues>& centroids) {
  VtuCells cells;
  for (const auto& c : m.cells) cells.add(c.data(), static_cast<int>(c.size()));
  for (const auto& c : m.triangles) cells.add(c.data(), static_cast<int>(c.size()));
  std::vector<VtuField> point{{"displacement", 3, {}}, {"reaction", 3, {}}};
  for (int n = 0; n < m.node_count(); ++n)
    for (int c = 0; c < 3; ++c)
      point[0].values.push_back(s.displacement(n, c)), point[1].values.push_back(s.reaction(n, c));
  std::vector<VtuField> cell{{"stress", 6, {}}, {"strain", 6, {}}, {"material", 1, {}, true}};
  for (const auto& v : centroids)
    for (int k = 0; k < 6; ++k) cell[0].values.push_back(v.stress(k)), cell[1].values.push_back(v.strain(k));
  for (std::size_t e = 0; e < m.cells.size(); ++e) cell[2].values.push_back(m.cell_tag(e).material + 1);
  for (std::size_t e = 0; e < m.triangles.size(); ++e)
    cell[2].values.push_back(m.triangle_tag(e).material + 1);
  write_vtu(path, m.nodes, cells, point, cell);
}

}  // namespace gapfe

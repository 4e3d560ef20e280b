#pragma once
// VTK XML unstructured grid for ParaView: the meridian plane as x = r, y = z, and the PVD collection
// that strings one file per load step together. Arrays are VTK's inline binary format (base64 of a
// UInt32 byte count and the little-endian values): exact doubles, and several times faster to write
// than text, which matters when every contact increment writes a file.
//
// Files are written whole through write_file_atomically_from (output/output_file.hpp), so an interrupted run
// never leaves a half-written file under the final name.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/workers.hpp"
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
/// into `s` (resized once): at 1e6 nodes these arrays are 100 MB of text, encoded on the pool's threads
/// (core/workers.hpp) in pieces of whole 3-byte groups, each into its own part of `s`.
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
  char* const out   = s.data() + start;
  const auto encode = [&](std::size_t group, std::uint32_t b) {  // stream bytes 3 group .. 3 group + 2
    char* o = out + 4 * group;
    o[0] = kDigits[b >> 18], o[1] = kDigits[(b >> 12) & 63], o[2] = kDigits[(b >> 6) & 63],
    o[3] = kDigits[b & 63];
  };
  const std::size_t whole = n / 3;  // groups of three stream bytes
  // The groups holding header bytes (the first two), then the data's in pieces: group g >= 2 is data
  // bytes 3 g - 4 .. 3 g - 2.
  for (std::size_t g = 0; g < std::min<std::size_t>(whole, 2); ++g)
    encode(g, at(3 * g) << 16 | at(3 * g + 1) << 8 | at(3 * g + 2));
  constexpr std::size_t kGroupsPerTask = std::size_t(1) << 18;  // 768 KiB of data
  const std::size_t data_groups        = whole > 2 ? whole - 2 : 0;
  parallel_for((data_groups + kGroupsPerTask - 1) / kGroupsPerTask, [&](std::size_t task) {
    const std::size_t first = 2 + task * kGroupsPerTask, last = std::min(whole, first + kGroupsPerTask);
    const unsigned char* d = data + (3 * first - sizeof bytes);
    for (std::size_t g = first; g < last; ++g, d += 3)
      encode(g, std::uint32_t(d[0]) << 16 | std::uint32_t(d[1]) << 8 | d[2]);
  });
  char* end = out + 4 * whole;
  if (const std::size_t rest = n - 3 * whole; rest > 0) {
    const std::uint32_t b = at(3 * whole) << 16 | (rest > 1 ? at(3 * whole + 1) << 8 : 0u);
    encode(whole, b);
    end += 4;
    end[-2] = rest > 1 ? end[-2] : '=';
    end[-1] = '=';
  }
  *end = '\n';
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
/// (detail::append_array), for arrays a series of files repeats unchanged. Written array by array through
/// one buffer (at 1e6 nodes the file is 110 MB, its largest array 32 MB).
inline void write_vtu(const std::string& path, const VtuMesh& mesh, const std::vector<VtuField>& point_data,
                      const std::vector<VtuField>& cell_data, const std::string& cell_xml = {}) {
  detail::write_file_atomically_from(path, [&](const auto& put) {
    std::string s =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
        "byte_order=\"LittleEndian\">\n";
    s += "<UnstructuredGrid><Piece NumberOfPoints=\"" + std::to_string(mesh.points) + "\" NumberOfCells=\"" +
         std::to_string(mesh.cells) + "\">\n";
    put(s);
    put(mesh.xml);
    put("<PointData>\n");
    for (const auto& f : point_data) s.clear(), detail::append_array(s, f), put(s);
    put("</PointData>\n<CellData>\n");
    for (const auto& f : cell_data) s.clear(), detail::append_array(s, f), put(s);
    put(cell_xml);
    put("</CellData>\n</Piece></UnstructuredGrid></VTKFile>\n");
  });
}

/// The parallel file (.pvtu) of a partitioned run's increment, for ParaView: the arrays every piece holds
/// (their names, types and components; `point_data` and `cell_data` as one piece's, their values unused) and
/// the pieces, `pieces` (file names relative to the .pvtu's folder). The pieces share no cells; their shared
/// nodes appear in each.
inline void write_pvtu(const std::string& path, const std::vector<std::string>& pieces,
                       const std::vector<VtuField>& point_data, const std::vector<VtuField>& cell_data) {
  const auto declare = [](std::string& s, const VtuField& f) {
    s += std::string("<PDataArray type=\"") + (f.integer ? "Int32" : "Float64") + "\" Name=\"" + f.name +
         "\" NumberOfComponents=\"" + std::to_string(f.components) + "\"/>\n";
  };
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n";
  for (const VtuField& f : point_data) declare(s, f);
  s += "</PPointData>\n<PCellData>\n";
  for (const VtuField& f : cell_data) declare(s, f);
  s += "</PCellData>\n<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n";
  for (const std::string& piece : pieces) s += "<Piece Source=\"" + piece + "\"/>\n";
  s += "</PUnstructuredGrid>\n</VTKFile>\n";
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

#pragma once
// VTK XML unstructured grid (ASCII) for ParaView: the meridian plane as x = r, y = z. Point data:
// displacement (u_r, u_z, u_theta) and reaction; cell data: centroid stress and strain in global
// Voigt order [rr, zz, hoop, rz, z-theta, theta-r] and the material index.
#include <cstdio>
#include <fstream>
#include <string>

#include "gapfe/core/error.hpp"
#include "gapfe/driver/linear_static.hpp"

namespace gapfe {

namespace detail {
inline int vtk_cell_type(int nodes) {
  return nodes == 3 ? 5 : nodes == 4 ? 9 : 23;
}  // triangle, quad, quad8
}  // namespace detail

/// Write `path`; throws InputError when the file cannot be written (nothing half-written is left
/// behind under the final name: the file is written to path + ".tmp" and renamed).
template <class M>
void write_vtu(const std::string& path, const LinearStatic<M>& fe) {
  const auto& m         = fe.problem().mesh;
  const auto& s         = fe.solution();
  const auto cells      = fe.centroid_values();
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw InputError("cannot write " + path);
    out.precision(12);
    const std::size_t nc = m.cells.size() + m.triangles.size();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n"
        << "<UnstructuredGrid><Piece NumberOfPoints=\"" << m.node_count() << "\" NumberOfCells=\"" << nc
        << "\">\n"
        << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto& x : m.nodes) out << x(0) << ' ' << x(1) << " 0\n";
    out << "</DataArray></Points>\n<Cells><DataArray type=\"Int32\" Name=\"connectivity\" "
           "format=\"ascii\">\n";
    for (const auto& c : m.cells) {
      for (int n : c) out << n << ' ';
      out << '\n';
    }
    for (const auto& c : m.triangles) out << c[0] << ' ' << c[1] << ' ' << c[2] << '\n';
    out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    std::size_t off = 0;
    for (std::size_t e = 0; e < m.cells.size(); ++e) out << (off += m.cells[e].size()) << '\n';
    for (std::size_t e = 0; e < m.triangles.size(); ++e) out << (off += 3) << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t e = 0; e < m.cells.size(); ++e) out << detail::vtk_cell_type(M::Element::kNodes) << '\n';
    for (std::size_t e = 0; e < m.triangles.size(); ++e) out << "5\n";
    out << "</DataArray></Cells>\n<PointData Vectors=\"displacement\">\n";
    out << "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n"
        << s.displacement << "\n</DataArray>\n";
    out << "<DataArray type=\"Float64\" Name=\"reaction\" NumberOfComponents=\"3\" format=\"ascii\">\n"
        << s.reaction << "\n</DataArray>\n</PointData>\n<CellData>\n";
    for (const bool stress : {true, false}) {
      out << "<DataArray type=\"Float64\" Name=\"" << (stress ? "stress" : "strain")
          << "\" NumberOfComponents=\"6\" format=\"ascii\">\n";
      for (const auto& v : cells) out << (stress ? v.stress : v.strain).transpose() << '\n';
      out << "</DataArray>\n";
    }
    out << "<DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">\n";
    for (std::size_t e = 0; e < m.cells.size(); ++e) out << m.cell_tag(e).material + 1 << '\n';
    for (std::size_t e = 0; e < m.triangles.size(); ++e) out << m.triangle_tag(e).material + 1 << '\n';
    out << "</DataArray>\n</CellData>\n</Piece></UnstructuredGrid></VTKFile>\n";
    if (!out) throw InputError("error while writing " + path);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw InputError("cannot rename " + tmp + " to " + path);
}

}  // namespace gapfe

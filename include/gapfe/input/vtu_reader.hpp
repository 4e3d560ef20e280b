#pragma once
// Reading back what output/vtu_writer.hpp writes, for `gapfe plot` (the pictures of a finished run): a VTK
// XML UnstructuredGrid (.vtu) with inline arrays, `binary` (base64 of a UInt32 or UInt64 byte count and the
// little-endian values, uncompressed) or `ascii`, a ParaView collection (.pvd), and a partitioned run's
// parallel file (.pvtu), whose pieces are joined into one mesh. Not a general VTK reader:
// appended data and compressed arrays are refused by name. tests/check_output.py reads the same files with
// meshio (a reader independent of this one) and compares them with the CSV tables.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"
#include "gapfe/problem/field_arrays.hpp"

namespace gapfe {

namespace detail {

/// The value of attribute `name` in the tag text `tag` ("" when absent).
inline std::string xml_attribute(std::string_view tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto at         = tag.find(key);
  if (at == std::string_view::npos) return {};
  const auto end = tag.find('"', at + key.size());
  return end == std::string_view::npos ? std::string()
                                       : std::string(tag.substr(at + key.size(), end - at - key.size()));
}

/// A count attribute (NumberOfPoints, NumberOfComponents): a whole number from `least` to 2^31; InputError
/// else.
inline std::size_t xml_count(std::string_view tag, const std::string& attribute, const std::string& what,
                             std::size_t least) {
  const std::string text  = xml_attribute(tag, attribute);
  std::size_t v           = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || v < least || v > (1u << 31))
    throw InputError(what + ": " + attribute + " '" + text + "' is not a count");
  return v;
}

/// Bytes of base64 text (whitespace skipped); InputError on another character.
inline std::vector<unsigned char> base64_bytes(std::string_view text, const std::string& what) {
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t bits = 0;
  int count          = 0;
  for (const char c : text) {
    int v = -1;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    else if (c == '=' || c == ' ' || c == '\n' || c == '\r' || c == '\t')
      continue;
    else
      throw InputError(what + ": a character that is not base64 ('" + std::string(1, c) + "')");
    bits = bits << 6 | static_cast<std::uint32_t>(v);
    if (++count == 4) {
      out.push_back(static_cast<unsigned char>(bits >> 16));
      out.push_back(static_cast<unsigned char>(bits >> 8));
      out.push_back(static_cast<unsigned char>(bits));
      bits = 0, count = 0;
    }
  }
  if (count == 2) out.push_back(static_cast<unsigned char>(bits >> 4));
  if (count == 3)
    out.push_back(static_cast<unsigned char>(bits >> 10)),
        out.push_back(static_cast<unsigned char>(bits >> 2));
  return out;
}

/// One DataArray's values as doubles.
inline std::vector<double> vtu_values(std::string_view tag, std::string_view body, const std::string& what,
                                      const std::string& header_type) {
  const std::string type = xml_attribute(tag, "type"), format = xml_attribute(tag, "format");
  std::size_t size = type == "Float64" || type == "Int64" || type == "UInt64"   ? 8
                     : type == "Float32" || type == "Int32" || type == "UInt32" ? 4
                     : type == "UInt8" || type == "Int8"                        ? 1
                                                                                : 0;
  if (size == 0) throw InputError(what + ": data type '" + type + "' is not read");
  std::vector<double> out;
  if (format == "ascii") {
    std::istringstream in{std::string(body)};
    for (double v; in >> v;) out.push_back(v);
    if (!in.eof()) throw InputError(what + ": a value that is not a number");
    return out;
  }
  if (format != "binary") throw InputError(what + ": format '" + format + "' is not read (binary or ascii)");
  const std::vector<unsigned char> bytes = base64_bytes(body, what);
  const std::size_t head                 = header_type == "UInt64" ? 8 : 4;
  if (bytes.size() < head) throw InputError(what + ": no byte count");
  std::uint64_t count = 0;
  std::memcpy(&count, bytes.data(), head);  // little-endian, as the file declares
  if (count % size != 0 || count > bytes.size() - head)
    throw InputError(what + ": the byte count " + std::to_string(count) + " does not match the data");
  out.resize(count / size);
  const unsigned char* d = bytes.data() + head;
  for (std::size_t k = 0; k < out.size(); ++k, d += size) {
    if (type == "Float64") {
      double v;
      std::memcpy(&v, d, 8);
      out[k] = v;
    } else if (type == "Float32") {
      float v;
      std::memcpy(&v, d, 4);
      out[k] = v;
    } else if (type == "Int64") {
      std::int64_t v;
      std::memcpy(&v, d, 8);
      out[k] = static_cast<double>(v);
    } else if (type == "UInt64") {
      std::uint64_t v;
      std::memcpy(&v, d, 8);
      out[k] = static_cast<double>(v);
    } else if (type == "Int32") {
      std::int32_t v;
      std::memcpy(&v, d, 4);
      out[k] = v;
    } else if (type == "UInt32") {
      std::uint32_t v;
      std::memcpy(&v, d, 4);
      out[k] = v;
    } else if (type == "Int8") {
      std::int8_t v;
      std::memcpy(&v, d, 1);
      out[k] = v;
    } else
      out[k] = *d;
  }
  return out;
}

}  // namespace detail

/// Read a VTU file's text; `name` names it in errors.
inline VtuData read_vtu(std::string_view text, const std::string& name) {
  if (text.find("<VTKFile") == std::string_view::npos ||
      text.find("UnstructuredGrid") == std::string_view::npos)
    throw InputError(name + ": not a VTK XML UnstructuredGrid file");
  if (text.find("compressor=") != std::string_view::npos ||
      text.find("<AppendedData") != std::string_view::npos)
    throw InputError(name + ": compressed or appended data is not read (gapfe writes inline binary)");
  const auto tag_of = [&](const char* open) {  // the opening tag's text, InputError when missing
    const auto at    = text.find(open);
    const auto close = at == std::string_view::npos ? at : text.find('>', at);
    if (close == std::string_view::npos) throw InputError(name + ": no " + std::string(open + 1) + " tag");
    return text.substr(at, close - at);
  };
  const std::string header_type = detail::xml_attribute(tag_of("<VTKFile"), "header_type");
  VtuData d;
  std::vector<double> connectivity, offsets;
  const std::string_view piece = tag_of("<Piece");
  const std::size_t points     = detail::xml_count(piece, "NumberOfPoints", name, 0),
                    cells      = detail::xml_count(piece, "NumberOfCells", name, 0);
  std::string section;  // Points, Cells, PointData or CellData
  for (std::size_t at = 0; (at = text.find('<', at)) != std::string_view::npos;) {
    const std::size_t close = text.find('>', at);
    if (close == std::string_view::npos) throw InputError(name + ": a tag is not closed");
    const std::string_view tag = text.substr(at, close - at);
    for (const char* s : {"Points", "Cells", "PointData", "CellData"})
      if (tag == std::string("<") + s || tag.rfind(std::string("<") + s + " ", 0) == 0) section = s;
    if (tag.rfind("<DataArray", 0) != 0) {
      at = close;
      continue;
    }
    const std::size_t end = text.find("</DataArray>", close);
    if (end == std::string_view::npos) throw InputError(name + ": a DataArray is not closed");
    const std::string array = detail::xml_attribute(tag, "Name");
    const std::string what  = name + ", array '" + array + "'";
    std::vector<double> values =
        detail::vtu_values(tag, text.substr(close + 1, end - close - 1), what, header_type);
    const std::size_t components = detail::xml_attribute(tag, "NumberOfComponents").empty()
                                       ? 1
                                       : detail::xml_count(tag, "NumberOfComponents", what, 1);
    if (section == "Points") {
      if (components != 3 || values.size() % 3 != 0 || values.size() / 3 != points)
        throw InputError(what + ": expected 3 x NumberOfPoints values");
      for (std::size_t n = 0; n < points; ++n) {
        d.points.emplace_back(values[3 * n], values[3 * n + 1]);
        if (!d.points.back().allFinite())
          throw InputError(what + ": point " + std::to_string(n + 1) + " is not finite");
      }
    } else if (section == "Cells") {
      if (array == "connectivity") connectivity = std::move(values);
      if (array == "offsets") offsets = std::move(values);
    } else if (section == "PointData" || section == "CellData") {
      const std::size_t count = section == "PointData" ? points : cells;
      if (values.size() % components != 0 || values.size() / components != count)
        throw InputError(what + ": " + std::to_string(values.size()) + " values, expected " +
                         std::to_string(components) + " for each of " + std::to_string(count));
      const bool integer = detail::xml_attribute(tag, "type").find("Int") != std::string::npos;
      (section == "PointData" ? d.point_data : d.cell_data)
          .push_back({array, static_cast<int>(components), std::move(values), integer});
    }
    at = end;
  }
  if (d.points.size() != points || offsets.size() != cells)
    throw InputError(name + ": the points or the cells' offsets are missing");
  std::size_t from = 0;
  for (const double o : offsets) {
    if (!(o >= static_cast<double>(from) && o <= static_cast<double>(connectivity.size()) &&
          o == std::floor(o)))
      throw InputError(name +
                       ": the cells' offsets are not increasing whole numbers within the connectivity");
    const auto to = static_cast<std::size_t>(o);
    std::vector<int> cell;
    for (std::size_t k = from; k < to; ++k) {
      const double n = connectivity[k];
      if (!(n >= 0 && n < static_cast<double>(points)))
        throw InputError(name + ": a cell names a point that does not exist");
      cell.push_back(static_cast<int>(n));
    }
    d.cells.push_back(std::move(cell));
    from = to;
  }
  return d;
}

/// A ParaView collection's datasets: (timestep, file) in the order given.
inline std::vector<std::pair<double, std::string>> read_pvd(std::string_view text, const std::string& name) {
  std::vector<std::pair<double, std::string>> out;
  for (std::size_t at = 0; (at = text.find("<DataSet", at)) != std::string_view::npos;) {
    const auto close = text.find('>', at);
    if (close == std::string_view::npos) throw InputError(name + ": a DataSet tag is not closed");
    const std::string_view tag = text.substr(at, close - at);
    const std::string time     = detail::xml_attribute(tag, "timestep"),
                      file     = detail::xml_attribute(tag, "file");
    char* end                  = nullptr;
    const double t             = std::strtod(time.c_str(), &end);
    if (file.empty() || time.empty() || *end != '\0')
      throw InputError(name + ": a DataSet without a numeric timestep or a file");
    out.emplace_back(t, file);
    at = close;
  }
  return out;
}

/// A parallel file's (.pvtu) pieces: the Source of each Piece, in order.
inline std::vector<std::string> read_pvtu(std::string_view text, const std::string& name) {
  if (text.find("<VTKFile") == std::string_view::npos ||
      text.find("PUnstructuredGrid") == std::string_view::npos)
    throw InputError(name + ": not a VTK XML PUnstructuredGrid file");
  std::vector<std::string> pieces;
  for (std::size_t at = 0; (at = text.find("<Piece", at)) != std::string_view::npos;) {
    const auto close = text.find('>', at);
    if (close == std::string_view::npos) throw InputError(name + ": a Piece tag is not closed");
    const std::string source = detail::xml_attribute(text.substr(at, close - at), "Source");
    if (source.empty()) throw InputError(name + ": a Piece without a Source");
    pieces.push_back(source);
    at = close;
  }
  if (pieces.empty()) throw InputError(name + ": no Piece");
  return pieces;
}

/// The pieces of a parallel file as one mesh: their points one after another (a node the pieces share is in
/// each), their cells on those points, and each array joined. The pieces must hold the same arrays
/// (InputError naming `name` otherwise).
inline VtuData join_pieces(std::vector<VtuData> pieces, const std::string& name) {
  VtuData whole;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    VtuData& p        = pieces[k];
    const auto offset = static_cast<int>(whole.points.size());
    const auto join   = [&](std::vector<VtuField>& into, std::vector<VtuField>& from, const char* kind) {
      if (k == 0) return void(into = std::move(from));
      bool same = into.size() == from.size();
      for (std::size_t f = 0; same && f < from.size(); ++f)
        same = into[f].name == from[f].name && into[f].components == from[f].components;
      if (!same)
        throw InputError(name + ": piece " + std::to_string(k + 1) + " has other " + kind +
                           " arrays than the first");
      for (std::size_t f = 0; f < from.size(); ++f)
        into[f].values.insert(into[f].values.end(), from[f].values.begin(), from[f].values.end());
    };
    join(whole.point_data, p.point_data, "point");
    join(whole.cell_data, p.cell_data, "cell");
    whole.points.insert(whole.points.end(), p.points.begin(), p.points.end());
    for (std::vector<int>& cell : p.cells) {
      for (int& n : cell) n += offset;
      whole.cells.push_back(std::move(cell));
    }
  }
  return whole;
}

}  // namespace gapfe

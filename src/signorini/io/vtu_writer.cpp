#include "signorini/io/vtu_writer.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

namespace signorini {

namespace {

struct Appender {
  std::string header;  // XML
  std::string blob;    // appended binary data
  // Declares a DataArray whose bytes go to the blob; returns its XML line.
  template <typename T>
  std::string array(const std::string& type, const std::string& name, int comps, const std::vector<T>& v,
                    const std::vector<std::string>& comp_names = {}) {
    std::string s = fmt::format(R"(<DataArray type="{}" Name="{}" NumberOfComponents="{}" format="appended" offset="{}")",
                                type, name, comps, blob.size());
    for (size_t i = 0; i < comp_names.size(); ++i) s += fmt::format(R"( ComponentName{}="{}")", i, comp_names[i]);
    s += "/>\n";
    const std::uint64_t n = v.size() * sizeof(T);
    blob.append(reinterpret_cast<const char*>(&n), sizeof(n));
    blob.append(reinterpret_cast<const char*>(v.data()), n);
    return s;
  }
};

}  // namespace

std::string vtu_text(const VtuData& d) {
  Appender a;
  const auto& pts = *d.points;
  std::vector<double> xyz;
  xyz.reserve(3 * pts.size());
  for (auto& p : pts) xyz.insert(xyz.end(), {p(0), p(1), p(2)});
  std::vector<std::int64_t> conn, offsets;
  std::vector<std::uint8_t> types;
  for (auto* b : d.cells) {
    const ElementInfo& info = element_info(b->type);
    for (Index e = 0; e < b->size(); ++e) {
      const Index* c = b->element(e);
      for (int k = 0; k < info.num_nodes; ++k) conn.push_back(c[info.vtk_order[k]]);
      offsets.push_back(static_cast<std::int64_t>(conn.size()));
      types.push_back(static_cast<std::uint8_t>(info.vtk_type));
    }
  }
  std::string body;
  body += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", pts.size(), types.size());
  body += "<Points>\n" + a.array("Float64", "Points", 3, xyz) + "</Points>\n";
  body += "<Cells>\n";
  body += a.array("Int64", "connectivity", 1, conn);
  body += a.array("Int64", "offsets", 1, offsets);
  body += a.array("UInt8", "types", 1, types);
  body += "</Cells>\n<PointData>\n";
  for (auto& f : d.point_fields) body += a.array("Float64", f.name, f.components, f.values, f.component_names);
  body += "</PointData>\n<CellData>\n";
  for (auto& f : d.cell_fields) body += a.array("Float64", f.name, f.components, f.values, f.component_names);
  body += "</CellData>\n</Piece>\n";
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "<UnstructuredGrid>\n" + body + "</UnstructuredGrid>\n";
  out += "<AppendedData encoding=\"raw\">\n_";
  out += a.blob;
  out += "\n</AppendedData>\n</VTKFile>\n";
  return out;
}

std::string pvtu_text(const VtuData& d, const std::vector<std::string>& pieces) {
  auto arrays = [](const std::vector<VtuField>& fields) {
    std::string s;
    for (auto& f : fields) {
      s += fmt::format(R"(<PDataArray type="Float64" Name="{}" NumberOfComponents="{}")", f.name, f.components);
      for (size_t i = 0; i < f.component_names.size(); ++i) s += fmt::format(R"( ComponentName{}="{}")", i, f.component_names[i]);
      s += "/>\n";
    }
    return s;
  };
  std::string s = "<?xml version=\"1.0\"?>\n";
  s += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  s += "<PUnstructuredGrid GhostLevel=\"0\">\n";
  s += "<PPoints>\n<PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  s += "<PCells>\n<PDataArray type=\"Int64\" Name=\"connectivity\" NumberOfComponents=\"1\"/>\n"
       "<PDataArray type=\"Int64\" Name=\"offsets\" NumberOfComponents=\"1\"/>\n"
       "<PDataArray type=\"UInt8\" Name=\"types\" NumberOfComponents=\"1\"/>\n</PCells>\n";
  s += "<PPointData>\n" + arrays(d.point_fields) + "</PPointData>\n";
  s += "<PCellData>\n" + arrays(d.cell_fields) + "</PCellData>\n";
  for (auto& p : pieces) s += fmt::format("<Piece Source=\"{}\"/>\n", p);
  s += "</PUnstructuredGrid>\n</VTKFile>\n";
  return s;
}

std::string pvd_text(const std::vector<std::pair<Real, std::string>>& entries) {
  std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n<Collection>\n";
  for (auto& [t, f] : entries) s += fmt::format("  <DataSet timestep=\"{:.10g}\" part=\"0\" file=\"{}\"/>\n", t, f);
  s += "</Collection>\n</VTKFile>\n";
  return s;
}

}  // namespace signorini

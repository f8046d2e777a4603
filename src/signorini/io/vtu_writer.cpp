#include "signorini/io/vtu_writer.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <sstream>

#include "signorini/io/atomic_file.hpp"

namespace signorini {

namespace {

// The appended data's arrays, each declared in the XML with its offset (computed from the
// sizes alone) and then streamed to the file in chunks: no copy of the file, nor of any whole
// array, is held in memory (at 1.4M DOFs the text and its copies were 1-2 GB per rank).
class Blob {
 public:
  explicit Blob(std::ostream& out) : out_(out) { buffer_.reserve(kChunk); }
  // A DataArray of `bytes` bytes of `type` values in `comps` components; its XML line.
  std::string declare(const std::string& type, const std::string& name, int comps, std::uint64_t bytes,
                      const std::vector<std::string>& comp_names = {}) {
    std::string s = fmt::format(R"(<DataArray type="{}" Name="{}" NumberOfComponents="{}" format="appended" offset="{}")",
                                type, name, comps, offset_);
    for (size_t i = 0; i < comp_names.size(); ++i) s += fmt::format(R"( ComponentName{}="{}")", i, comp_names[i]);
    s += "/>\n";
    offset_ += sizeof(std::uint64_t) + bytes;
    return s;
  }
  // An array's bytes: its byte count first, then its values (put) in order.
  void begin(std::uint64_t bytes) { raw(&bytes, sizeof(bytes)); }
  template <typename T>
  void put(T v) {
    raw(&v, sizeof(T));
  }
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr size_t kChunk = 1 << 20;
  void raw(const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    buffer_.insert(buffer_.end(), c, c + n);
    if (buffer_.size() >= kChunk) flush();
  }
  std::ostream& out_;
  std::vector<char> buffer_;
  std::uint64_t offset_ = 0;
};

}  // namespace

void write_vtu(std::ostream& out, const VtuData& d) {
  Blob blob(out);
  const auto& pts = *d.points;
  std::uint64_t cells = 0, refs = 0;
  for (auto* b : d.cells) {
    cells += static_cast<std::uint64_t>(b->size());
    refs += static_cast<std::uint64_t>(b->size()) * static_cast<std::uint64_t>(element_info(b->type).num_nodes);
  }
  auto values_of = [](const VtuField& f) { return static_cast<std::uint64_t>(f.values.size()) * sizeof(double); };
  std::string body;
  body += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", pts.size(), cells);
  body += "<Points>\n" + blob.declare("Float64", "Points", 3, 3 * sizeof(double) * pts.size()) + "</Points>\n";
  body += "<Cells>\n";
  body += blob.declare("Int64", "connectivity", 1, refs * sizeof(std::int64_t));
  body += blob.declare("Int64", "offsets", 1, cells * sizeof(std::int64_t));
  body += blob.declare("UInt8", "types", 1, cells);
  body += "</Cells>\n<PointData>\n";
  for (auto& f : d.point_fields) body += blob.declare("Float64", f.name, f.components, values_of(f), f.component_names);
  body += "</PointData>\n<CellData>\n";
  for (auto& f : d.cell_fields) body += blob.declare("Float64", f.name, f.components, values_of(f), f.component_names);
  body += "</CellData>\n</Piece>\n";
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n"
      << body << "</UnstructuredGrid>\n"
      << "<AppendedData encoding=\"raw\">\n_";
  blob.begin(3 * sizeof(double) * pts.size());
  for (auto& p : pts)
    for (int k = 0; k < 3; ++k) blob.put(static_cast<double>(p(k)));
  blob.begin(refs * sizeof(std::int64_t));
  for (auto* b : d.cells) {
    const ElementInfo& info = element_info(b->type);
    for (Index e = 0; e < b->size(); ++e)
      for (int k = 0; k < info.num_nodes; ++k) blob.put(static_cast<std::int64_t>(b->element(e)[info.vtk_order[k]]));
  }
  blob.begin(cells * sizeof(std::int64_t));
  std::int64_t offset = 0;
  for (auto* b : d.cells) {
    const int nn = element_info(b->type).num_nodes;
    for (Index e = 0; e < b->size(); ++e) blob.put(offset += nn);
  }
  blob.begin(cells);
  for (auto* b : d.cells) {
    const auto type = static_cast<std::uint8_t>(element_info(b->type).vtk_type);
    for (Index e = 0; e < b->size(); ++e) blob.put(type);
  }
  for (const auto* fields : {&d.point_fields, &d.cell_fields})
    for (auto& f : *fields) {
      blob.begin(values_of(f));
      for (Real v : f.values) blob.put(static_cast<double>(v));
    }
  blob.flush();
  out << "\n</AppendedData>\n</VTKFile>\n";
}

std::string vtu_text(const VtuData& d) {
  std::ostringstream s;
  write_vtu(s, d);
  return s.str();
}

void write_vtu_file(const std::string& path, const VtuData& d) {
  write_file_atomically(path, [&](std::ostream& out) { write_vtu(out, d); });
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

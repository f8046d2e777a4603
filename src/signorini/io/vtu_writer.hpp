// ParaView output: one VTU (unstructured grid, binary appended data) per written increment
// and a PVD collection that lists them with their pseudo-time. Under mpirun with the cells
// shared out, each rank writes the piece of its own cells and a PVTU joins the pieces.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

struct VtuField {
  std::string name;
  int components = 1;
  std::vector<Real> values;  // components per point or per cell
  std::vector<std::string> component_names;
};

struct VtuData {
  const std::vector<Vec3>* points = nullptr;
  std::vector<const ElementBlock*> cells;
  std::vector<VtuField> point_fields;
  std::vector<VtuField> cell_fields;
};

// Writes a .vtu file's XML and appended binary data to `out`, streamed (nothing of the size
// of the file is held in memory).
void write_vtu(std::ostream& out, const VtuData& data);
// The same into `path`, atomically (write_file_atomically).
void write_vtu_file(const std::string& path, const VtuData& data);
// Returns the text write_vtu writes (for tests and small files).
std::string vtu_text(const VtuData& data);
// Returns the XML text of a .pvtu file that joins `pieces` (.vtu files, each written by
// write_vtu from data with the same fields as `data`) into one dataset.
std::string pvtu_text(const VtuData& data, const std::vector<std::string>& pieces);
// Returns the XML text of a .pvd listing (time, file) pairs.
std::string pvd_text(const std::vector<std::pair<Real, std::string>>& entries);

}  // namespace signorini

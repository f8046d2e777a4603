// ParaView output: one VTU (unstructured grid, binary appended data) per written increment
// and a PVD collection that lists them with their pseudo-time. Under mpirun with the cells
// shared out, each rank writes the piece of its own cells and a PVTU joins the pieces.
#pragma once
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

// Returns the XML text of a .vtu file.
std::string vtu_text(const VtuData& data);
// Returns the XML text of a .pvtu file that joins `pieces` (.vtu files, each written by
// vtu_text from data with the same fields as `data`) into one dataset.
std::string pvtu_text(const VtuData& data, const std::vector<std::string>& pieces);
// Returns the XML text of a .pvd listing (time, file) pairs.
std::string pvd_text(const std::vector<std::pair<Real, std::string>>& entries);

}  // namespace signorini

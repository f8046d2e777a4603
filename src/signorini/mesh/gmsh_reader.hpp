// Reads a Gmsh mesh (.msh 2.2 or 4.1) or meshes a .geo file at run time through the Gmsh
// API. Physical groups become named regions (cells), facet sets and node sets.
#pragma once
#include <map>
#include <string>

#include "signorini/mesh/mesh.hpp"

namespace signorini {

class RankExchange;

struct GmshOptions {
  std::map<std::string, Real> parameters;  // .geo constants, declared with DefineConstant
  int order = 0;                           // element order to set after meshing (0: as is)
  std::string where;                       // deck location for error messages
  bool trusted = false;                    // run a .geo's side effects (geo_side_effect)
  double max_elements = 2e7;               // a .geo meshing beyond this (estimated) stops with an error
  // Under mpirun (every rank reads the deck): rank 0 alone reads the mesh (runs the gmsh
  // program, meshing a .geo or checking a .msh, and parses its output through the API) and
  // sends the other ranks its verdict and then the Mesh, so that a node's ranks do not each
  // mesh and parse (p times Gmsh's memory and time) and every rank holds the same mesh. Null
  // (one process): this process reads it.
  const RankExchange* ranks = nullptr;
};

// The elements of a .geo meshed with every size multiplied by `size_factor` (Gmsh's
// -clscale), counted by a gmsh process `exe`; -1 if that meshing failed or took more than
// `timeout` seconds. `dim` receives the mesh's dimension.
double count_elements(const std::string& exe, const std::string& geo, const std::vector<std::string>& args,
                      double size_factor, double timeout, int* dim);

// The element count of the .geo's mesh, estimated from coarser meshes of it (sizes scaled by
// 4^k, from 4^20 down, until one has 2000 elements or more: N(1) ~ N(s) s^dim).
double estimate_elements(const std::string& exe, const std::string& geo, const std::vector<std::string>& args);

// The first side effect of a .geo script outside plain geometry and meshing, as a message
// naming its line ("" if none): SystemCall, Exit, Save, Print, OnelabRun, and Include or Merge
// of a file outside the script's folder (absolute, or reaching up with ".."). Comments and
// string contents are skipped. A .geo is a program; `signorini check` must not run commands.
std::string geo_side_effect(const std::string& text);

// A .msh is first read by a gmsh process of its own when the gmsh program is installed
// (check_msh_in_child): a malformed file that would crash or hang Gmsh's parser is an
// InputError; then this process reads it.
Mesh read_gmsh(const std::string& path, const GmshOptions& options = {});
void check_msh_in_child(const std::string& exe, const std::string& msh, const std::string& where);

// Every node and the corners of every 2D element (triangles, quadrilaterals; mid-side nodes
// left out) of a Gmsh .msh file, with or without physical groups: the surfaces of the
// contact search benchmark. Throws InputError naming the file.
struct SurfaceFile {
  std::vector<Vec3> nodes;
  std::vector<Vec3> triangles;  // 3 corners per triangle
  std::vector<Vec3> quads;      // 4 corners per quadrilateral
};
SurfaceFile read_surface_file(const std::string& path);

}  // namespace signorini

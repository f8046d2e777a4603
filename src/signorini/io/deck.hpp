// Reads a YAML deck into a Model, validating every key against the registry. An error
// names the file, the line, the key and what was expected; unknown keys are errors.
#pragma once
#include <string>

#include "signorini/fem/model.hpp"
#include "signorini/io/registry.hpp"

namespace signorini {

class RankExchange;

struct DeckReport {
  int reoriented_cells = 0;   // cells whose node order was mirrored on load
  Index orphan_facets = 0;    // facets of a facet set that belong to no cell
};

// `ranks` (under mpirun, every rank reading the deck): rank 0 alone reads a Gmsh mesh (meshes
// the .geo or checks the .msh, and parses it) and sends it to the others (GmshOptions::ranks).
Model read_deck(const std::string& path, const Registry& registry, DeckReport* report = nullptr,
                const RankExchange* ranks = nullptr);

}  // namespace signorini

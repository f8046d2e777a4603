// Reads the CalculiX / Abaqus input (.inp) subset that contact users write, and translates
// it into the equivalent Signorini deck (docs/deck.md, "CalculiX and Abaqus decks").
// The mesh part (*NODE, *ELEMENT, *NSET, *ELSET, *SURFACE) becomes a Mesh; the model
// (*MATERIAL, *SOLID SECTION, *CONTACT PAIR, *STEP, ...) becomes YAML text that the deck
// reader then validates like any deck, each YAML line remembering the .inp line that wrote
// it, so that every message names the .inp file, line and keyword.
#pragma once
#include <string>
#include <vector>

#include "signorini/mesh/mesh.hpp"

namespace signorini {

struct InpDeck {
  Mesh mesh;
  std::string yaml;                 // the equivalent deck (its mesh: {file: <the .inp>})
  std::vector<std::string> origin;  // origin[k]: "file:line (*KEYWORD)" that wrote YAML line k
};

// The whole deck. Unsupported keywords are errors naming file, line and keyword; output
// requests and *CONTROLS get a one-line notice (log::info).
InpDeck read_inp(const std::string& path);

// The mesh alone (nodes, elements, node and element sets, surfaces), for a YAML deck whose
// mesh.file is an .inp: elements sets become regions (and EALL all elements), node sets
// (and NALL) node sets, element-face surfaces facet sets, node surfaces node sets and the
// facet set of the exterior facets whose nodes all belong to them. Names are upper case.
Mesh read_inp_mesh(const std::string& path);

}  // namespace signorini

// One registry of everything chosen at run time (materials, linear solvers) and of the
// deck sections, each with its parameters: doc string, default and range. The deck parser
// validates against it and `signorini describe` prints the same text the docs show.
#pragma once
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/material/material.hpp"

namespace signorini {

enum class ParamKind { number, integer, boolean, string, vector, any };

struct ParamSpec {
  std::string name;
  ParamKind kind = ParamKind::number;
  std::string doc;
  std::optional<std::string> default_text;  // shown in docs; absent: required (unless optional)
  bool optional = false;                    // may be absent without a default
  Real min = -std::numeric_limits<Real>::infinity();
  Real max = std::numeric_limits<Real>::infinity();
  bool min_open = false, max_open = false;  // exclusive bounds
  std::vector<std::string> choices;         // for strings
  bool required() const { return !default_text && !optional; }
  // Empty if v is acceptable, else what is expected.
  std::string check_number(Real v) const;
  std::string range_text() const;
};

struct TypeSpec {
  std::string category;  // material, linear_solver, deck
  std::string name;
  std::string doc;
  std::vector<ParamSpec> params;
  const ParamSpec* param(const std::string& n) const;
};

using ParamValues = std::map<std::string, Real>;
using MaterialFactory = std::function<std::shared_ptr<Material>(const ParamValues&)>;

class Registry {
 public:
  void add(TypeSpec spec);
  void add_material(TypeSpec spec, MaterialFactory factory);
  const TypeSpec* find(const std::string& category, const std::string& name) const;
  const TypeSpec* find_any(const std::string& name) const;
  std::vector<const TypeSpec*> all() const;
  std::vector<std::string> names(const std::string& category) const;
  std::shared_ptr<Material> make_material(const std::string& name, const ParamValues& p) const;
  // Human-readable description (also used to write docs/deck.md's parameter tables).
  std::string describe(const TypeSpec& spec) const;

 private:
  std::vector<TypeSpec> specs_;
  std::map<std::string, MaterialFactory> materials_;
};

// Fills a registry with everything Signorini ships.
void register_materials(Registry& r);
void register_linear_solvers(Registry& r);
void register_deck_sections(Registry& r);
Registry default_registry();

}  // namespace signorini

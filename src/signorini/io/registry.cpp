#include "signorini/io/registry.hpp"

#include <fmt/format.h>

#include <cmath>

#include "signorini/core/error.hpp"
#include "signorini/material/j2_plasticity.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini {

std::string ParamSpec::range_text() const {
  if (!choices.empty()) {
    std::string s = "one of ";
    for (size_t i = 0; i < choices.size(); ++i) s += (i ? ", " : "") + choices[i];
    return s;
  }
  if (kind != ParamKind::number && kind != ParamKind::integer) return "";
  const bool lo = std::isfinite(min), hi = std::isfinite(max);
  if (!lo && !hi) return "";
  std::string s;
  if (lo) s += fmt::format("{}{}", min_open ? "> " : ">= ", min);
  if (lo && hi) s += " and ";
  if (hi) s += fmt::format("{}{}", max_open ? "< " : "<= ", max);
  return s;
}

std::string ParamSpec::check_number(Real v) const {
  if (!std::isfinite(v)) return "a finite number";
  if (kind == ParamKind::integer && v != std::round(v)) return "an integer";
  if ((v < min || (min_open && v == min)) || (v > max || (max_open && v == max))) return "a value " + range_text();
  return "";
}

const ParamSpec* TypeSpec::param(const std::string& n) const {
  for (auto& p : params)
    if (p.name == n) return &p;
  return nullptr;
}

void Registry::add(TypeSpec spec) { specs_.push_back(std::move(spec)); }

void Registry::add_material(TypeSpec spec, MaterialFactory factory) {
  materials_[spec.name] = std::move(factory);
  specs_.push_back(std::move(spec));
}

const TypeSpec* Registry::find(const std::string& category, const std::string& name) const {
  for (auto& s : specs_)
    if (s.category == category && s.name == name) return &s;
  return nullptr;
}

const TypeSpec* Registry::find_any(const std::string& name) const {
  for (auto& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

std::vector<const TypeSpec*> Registry::all() const {
  std::vector<const TypeSpec*> v;
  for (auto& s : specs_) v.push_back(&s);
  return v;
}

std::vector<std::string> Registry::names(const std::string& category) const {
  std::vector<std::string> v;
  for (auto& s : specs_)
    if (s.category == category) v.push_back(s.name);
  return v;
}

std::shared_ptr<Material> Registry::make_material(const std::string& name, const ParamValues& p) const {
  auto it = materials_.find(name);
  if (it == materials_.end()) throw Error("unknown material model '" + name + "'");
  return it->second(p);
}

std::string Registry::describe(const TypeSpec& spec) const {
  std::string s = fmt::format("{} ({})\n  {}\n", spec.name, spec.category, spec.doc);
  if (spec.params.empty()) return s + "  (no parameters)\n";
  s += "  parameters:\n";
  for (auto& p : spec.params) {
    std::string extra;
    if (p.default_text) extra += "default " + *p.default_text;
    else if (p.optional) extra += "optional";
    else extra += "required";
    const std::string range = p.range_text();
    if (!range.empty()) extra += "; " + range;
    s += fmt::format("    {:<22} {} [{}]\n", p.name, p.doc, extra);
  }
  return s;
}

namespace {
ParamSpec number(std::string name, std::string doc, std::optional<std::string> def = std::nullopt,
                 Real min = -INFINITY, Real max = INFINITY, bool min_open = false, bool max_open = false) {
  ParamSpec p;
  p.name = std::move(name);
  p.doc = std::move(doc);
  p.default_text = std::move(def);
  p.min = min;
  p.max = max;
  p.min_open = min_open;
  p.max_open = max_open;
  return p;
}
ParamSpec choice(std::string name, std::string doc, std::vector<std::string> choices, std::optional<std::string> def) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = ParamKind::string;
  p.doc = std::move(doc);
  p.choices = std::move(choices);
  p.default_text = std::move(def);
  return p;
}
ParamSpec text(std::string name, std::string doc, std::optional<std::string> def, ParamKind kind = ParamKind::string) {
  ParamSpec p;
  p.name = std::move(name);
  p.kind = kind;
  p.doc = std::move(doc);
  p.default_text = std::move(def);
  return p;
}
ParamSpec opt(ParamSpec p) {
  p.optional = true;
  return p;
}
}  // namespace

void register_materials(Registry& r) {
  const std::string model_doc = "material model name";
  r.add_material({"material", "linear_elastic",
                  "Isotropic linear elasticity (small strain); Saint Venant-Kirchhoff S = C:E in finite strain.",
                  {choice("model", model_doc, {"linear_elastic"}, std::nullopt),
                   number("E", "Young's modulus", std::nullopt, 0, INFINITY, true),
                   number("nu", "Poisson's ratio", std::nullopt, -1, 0.5, true, true)}},
                 [](const ParamValues& p) { return std::make_shared<LinearElastic>(p.at("E"), p.at("nu")); });
  r.add_material({"material", "neo_hookean",
                  "Compressible Neo-Hookean, S = mu (I - C^-1) + lambda ln J C^-1 (Bonet & Wood 2008, eq. 6.28); "
                  "linear elastic in small strain.",
                  {choice("model", model_doc, {"neo_hookean"}, std::nullopt),
                   number("E", "Young's modulus (small-strain limit)", std::nullopt, 0, INFINITY, true),
                   number("nu", "Poisson's ratio (small-strain limit)", std::nullopt, -1, 0.5, true, true)}},
                 [](const ParamValues& p) { return std::make_shared<NeoHookean>(p.at("E"), p.at("nu")); });
  r.add_material({"material", "j2_plasticity",
                  "Von Mises (J2) plasticity, radial return with the consistent tangent (Simo & Hughes 1998, Box "
                  "3.2); isotropic hardening linear or Voce, linear kinematic hardening (small strain only); "
                  "perfectly plastic without 'hardening'. With kinematics: finite_strain, the multiplicative model "
                  "F = F_e F_p with a Hencky elastic law and the exponential map (Simo 1992; Eterovic & Bathe "
                  "1990). With a viscosity, Perzyna viscoplasticity (backward Euler; the steps' `time` sets the "
                  "rate). History output: plastic strain (small) or plastic deformation gradient F_p (finite), "
                  "equivalent plastic strain, back stress (small), plastic work, plastic dissipation, yielding (1 "
                  "where the last increment yielded).",
                  {choice("model", model_doc, {"j2_plasticity"}, std::nullopt),
                   number("E", "Young's modulus", std::nullopt, 0, INFINITY, true),
                   number("nu", "Poisson's ratio", std::nullopt, -1, 0.5, true, true),
                   number("yield_stress", "initial yield stress sigma_y0 (uniaxial)", std::nullopt, 0, INFINITY, true),
                   opt(text("hardening", "{isotropic: {...}, kinematic: {...}} (see 'describe hardening'); absent: "
                                         "perfectly plastic", std::nullopt, ParamKind::any)),
                   number("viscosity", "Perzyna viscosity eta (time, in the steps' `time` units): d(alpha)/dt = "
                                       "(1/eta) <q/sigma_y - 1>^m; 0: rate independent",
                          "0", 0, INFINITY),
                   number("rate_exponent", "Perzyna rate exponent m (with a viscosity)", "1", 0, INFINITY, true)}},
                 [](const ParamValues& p) {
                   J2Hardening h;
                   auto get = [&](const char* k) { return p.count(k) ? p.at(k) : 0.0; };
                   h.H = get("hardening.isotropic.H");
                   h.voce = get("hardening.isotropic.voce") != 0;
                   h.saturation = get("hardening.isotropic.saturation");
                   h.rate = get("hardening.isotropic.rate");
                   h.kinematic = get("hardening.kinematic.H");
                   const bool finite = p.count("finite_strain") && p.at("finite_strain") != 0;
                   const J2Viscosity v{p.count("viscosity") ? p.at("viscosity") : 0.0,
                                       p.count("rate_exponent") ? p.at("rate_exponent") : 1.0};
                   return std::make_shared<J2Plasticity>(p.at("E"), p.at("nu"), p.at("yield_stress"), h, finite, v);
                 });
}

void register_linear_solvers(Registry& r) {
  r.add({"linear_solver", "auto",
         "CHOLMOD for symmetric systems, and for symmetric 3D systems above 200000 unknowns (linear: "
         "{iterative_above: ...}) gamg (eigen_cg in a build without PETSc), or whose Cholesky factor would hold more "
         "than 5e7 entries (linear: {direct_factor_limit: ...}; with PETSc) gamg; unsymmetric systems: UMFPACK, with "
         "PETSc MUMPS's LU above 10000 unknowns (UMFPACK if MUMPS fails); MUMPS's LDL^T (or "
         "UMFPACK) when Cholesky or the iterative solver fails. Lagrange friction on a 3D model (with PETSc; in 2D "
         "above iterative_above): its multipliers condensed node by node, GMRES over gamg. Unsymmetric systems "
         "without multipliers on a 3D model (penalty friction, follower pressure; with PETSc): GMRES over gamg, LU "
         "where it fails. In both cases, at or below iterative_above, the whole system goes to LU (MUMPS above 10000 "
         "unknowns) for the rest of the run once a forecast from the Krylov iterations (10 K nnz / n^2 above 1) "
         "favours the factorization. Under mpirun: gamg for symmetric 3D systems above iterative_above (contact multipliers condensed) and for "
         "unsymmetric 3D systems of any size (Lagrange friction's multipliers condensed, or none), the whole system "
         "to mumps where they cannot be condensed, where GMRES fails, or after the forecast; mumps otherwise.",
         {}});
  r.add({"linear_solver", "cholmod", "SuiteSparse CHOLMOD supernodal Cholesky (symmetric positive definite). Symmetric systems only: a model whose tangent is unsymmetric (friction, follower pressure) is refused; contact multipliers are condensed for it.", {}});
  r.add({"linear_solver", "umfpack", "SuiteSparse UMFPACK multifrontal LU (any nonsingular matrix).", {}});
  r.add({"linear_solver", "eigen_ldlt", "Eigen simplicial LDLT, no pivoting (symmetric; always available, slower). Symmetric systems only: a model whose tangent is unsymmetric (friction, follower pressure) is refused; contact multipliers are condensed for it.", {}});
  r.add({"linear_solver", "eigen_lu", "Eigen SparseLU (general; always available, slower).", {}});
  r.add({"linear_solver", "eigen_cg",
         "Eigen conjugate gradients with incomplete Cholesky preconditioning, relative tolerance 1e-10 (symmetric "
         "positive definite; far less memory than a direct factor on large 3D problems). Symmetric systems only: a model whose tangent is unsymmetric (friction, follower pressure) is refused; contact multipliers are condensed for it.",
         {}});
  const std::string petsc = petsc_available() ? "" : " Not in this build (configured without PETSc).";
  r.add({"linear_solver", "gamg",
         "PETSc: conjugate gradients (GMRES when unsymmetric) with aggregation algebraic multigrid (smoothed; "
         "plain under adaptive forcing, whose solves redo a cheaper setup at each Newton iteration; connections below "
         "0.01 of the diagonal left out of the aggregation graph), the "
         "rigid-body modes as near-nullspace, interpolation reused while the pattern holds. Contact multipliers are "
         "condensed first (or use penalty)." + petsc,
         {}});
  r.add({"linear_solver", "hypre",
         "PETSc: conjugate gradients (GMRES when unsymmetric) with hypre's BoomerAMG. Contact multipliers are "
         "condensed first (or use penalty)." + petsc,
         {}});
  r.add({"linear_solver", "mumps", "PETSc: MUMPS direct LU, or LDL^T when symmetric (any nonsingular system)." + petsc,
         {}});
  r.add({"linear_solver", "petsc", "PETSc's defaults (GMRES, ILU(0)), set by the raw options." + petsc, {}});
}

void register_deck_sections(Registry& r) {
  std::vector<std::string> solvers = linear_solver_names();
  r.add({"deck", "deck", "Top level of a deck.",
         {text("title", "a title for the run", "\"\""),
          text("analysis", "analysis type and kinematics (see 'describe analysis')", std::nullopt, ParamKind::any),
          text("mesh", "the mesh (see 'describe mesh')", std::nullopt, ParamKind::any),
          text("materials", "named materials: name -> {model, parameters}", std::nullopt, ParamKind::any),
          text("bodies", "list of {name, region, material}", std::nullopt, ParamKind::any),
          text("steps", "list of load steps (see 'describe step')", std::nullopt, ParamKind::any),
          opt(text("solver", "Newton and linear solver settings (see 'describe solver')", std::nullopt, ParamKind::any)),
          opt(text("output", "output settings (see 'describe output')", std::nullopt, ParamKind::any)),
          opt(text("checks", "reference values to compare with after the run (see 'describe check')", std::nullopt,
                   ParamKind::any)),
          opt(text("contact", "list of contact pairs (see 'describe contact')", std::nullopt, ParamKind::any))}});
  r.add({"deck", "analysis", "Analysis type.",
         {choice("dimension", "type of analysis", {"plane_strain", "plane_stress", "axisymmetric", "3d"}, std::nullopt),
          choice("kinematics", "small strain, or finite strain (total Lagrangian)", {"small_strain", "finite_strain"},
                 "small_strain"),
          number("thickness", "out-of-plane thickness (plane strain and plane stress)", "1", 0, INFINITY, true)}});
  r.add({"deck", "mesh", "The mesh: a Gmsh .msh (2.2 or 4.1), a .geo meshed at run time, or the mesh of a CalculiX/Abaqus .inp.",
         {text("file", "path, relative to the deck", std::nullopt),
          opt(text("parameters", ".geo constants declared with DefineConstant[...]: name -> number", std::nullopt,
                   ParamKind::any)),
          number("order", "element order to raise the mesh to after meshing (0: keep)", "0", 0, 2),
          number("scale", "factor on every node coordinate after reading, e.g. 1e-3 for a mesh drawn in mm in a deck "
                          "in m (the .geo's parameters are in the mesh's own units)",
                 "1", 1e-300, 1e300),
          text("trusted", "run the .geo's side effects (SystemCall, Exit, Save, Print, OnelabRun, Include or Merge "
                          "of files outside its folder), which are refused otherwise",
               "false", ParamKind::boolean),
          number("max_elements", "a .geo whose meshing takes more than 5 s has its element count estimated (from "
                                 "coarser meshes of it); above this many elements the meshing stops with the estimate",
                 "20000000", 1, 1e15)}});
  r.add({"deck", "body", "A body: the cells of one region with one material, or rigid.",
         {text("name", "name used in messages and output", std::nullopt),
          text("region", "physical group of cells", std::nullopt),
          opt(text("material", "name of a material of the 'materials' section (deformable bodies)", std::nullopt)),
          text("rigid", "the body is rigid: all its nodes translate with its reference node (rotations locked)",
               "false", ParamKind::boolean),
          opt(text("reference", "rigid body: node set of its reference node (may lie outside the cells); boundary "
                                "conditions and forces on it drive the body",
                   std::nullopt))}});
  r.add({"deck", "step", "A load step. Prescribed values and loads ramp linearly over the step.",
         {text("name", "step name", "step<N>"),
          opt(text("increments", "{initial, min, max, max_count}: fractions of the step", std::nullopt, ParamKind::any)),
          number("time", "the step's duration (time units of the viscosities): an increment of fraction f lasts f "
                         "time; only rate-dependent materials read it", "1", 0, INFINITY, true),
          opt(text("boundary", "list of Dirichlet conditions (see 'describe boundary')", std::nullopt, ParamKind::any)),
          opt(text("loads", "list of loads (see 'describe load')", std::nullopt, ParamKind::any))}});
  r.add({"deck", "increments", "Increment control of a step (fractions of the step).",
         {number("initial", "first increment", "1", 0, 1, true, false),
          number("min", "smallest increment before giving up", "1e-5", 0, 1, true, false),
          number("max", "largest increment", "1", 0, 1, true, false),
          number("max_count", "largest number of increments in the step", "10000", 1, 1e9)}});
  r.add({"deck", "boundary", "Prescribed displacement on a node set: {set, u: [..]} or {set, ux|uy|uz: value}. A "
                             "value is a number (reached at the end of the step, ramped from the value at its start), "
                             "{ramp: [start, end]}, or hold (kept at the value the step begins with; ~ leaves it free).",
         {opt(text("set", "node set (physical group)", std::nullopt)),
          opt(text("contact", "instead of set: a contact pair whose rigid obstacle moves by u", std::nullopt)),
          opt(text("u", "all components", std::nullopt, ParamKind::vector)),
          opt(text("ux", "x (or r) component", std::nullopt, ParamKind::any)),
          opt(text("uy", "y (or z) component", std::nullopt, ParamKind::any)),
          opt(text("uz", "z component (3D)", std::nullopt, ParamKind::any)),
          opt(text("rotation", "the rotation of a rigid obstacle (with contact) about its point (a plane's point, a "
                               "cylinder's axis point, a sphere's centre), or of a meshed rigid body (set: its reference "
                               "node set) about its reference node: in plane strain and plane stress the angle about z "
                               "(radians, counter-clockwise), in 3D the rotation vector [x, y, z] (axis times angle, "
                               "each component ramped; one-to-one below an angle of pi)",
                   std::nullopt, ParamKind::any))}});
  r.add({"deck", "load", "A load, ramped from its value at the end of the previous step: exactly one of force "
                         "(total force on a node set, shared equally by its nodes), traction (per unit reference area "
                         "of a facet set), pressure (on a facet set, positive in compression, follower in finite "
                         "strain), body_force (per unit reference volume of a body) or centrifugal (of a body spinning "
                         "about an axis; see 'describe centrifugal'). The centrifugal load ramps omega^2.",
         {opt(text("set", "node set or facet set", std::nullopt)), opt(text("body", "body name (body_force)", std::nullopt)),
          opt(text("contact", "instead of set: a contact pair whose rigid obstacle the force pushes", std::nullopt)),
          opt(text("force", "total force vector", std::nullopt, ParamKind::vector)),
          opt(text("moment", "the moment on a rigid obstacle (with contact; about its point) or on a meshed rigid body "
                             "(set: its reference node set, the moment alone), its rotation then free: in plane strain "
                             "and plane stress a number (about z), in 3D a vector [x, y, z] fixed in space",
                   std::nullopt, ParamKind::any)),
          opt(text("traction", "traction vector", std::nullopt, ParamKind::vector)),
          opt(number("pressure", "pressure", std::nullopt)),
          opt(text("body_force", "force per unit volume", std::nullopt, ParamKind::vector)),
          opt(text("centrifugal", "{density, omega, axis, origin} (see 'describe centrifugal')", std::nullopt,
                   ParamKind::any))}});
  r.add({"deck", "centrifugal",
         "Centrifugal load of a body (key 'body') spinning at omega about an axis: rho omega^2 times the distance "
         "vector from the axis, per unit reference volume (a dead load on the reference configuration).",
         {number("density", "mass density rho (mass per unit volume, in the deck's units: force = mass x "
                            "length / time^2)", std::nullopt, 0, INFINITY, true),
          number("omega", "angular velocity (radians per unit time)", std::nullopt, 0, INFINITY),
          opt(text("axis", "3D: the axis direction [ax, ay, az] (required); 2D: the out-of-plane axis; axisymmetric: "
                           "the symmetry axis (neither may be given)", std::nullopt, ParamKind::vector)),
          opt(text("origin", "a point on the axis ([x, y] in 2D, [x, y, z] in 3D; default the origin; not in "
                             "axisymmetry)", std::nullopt, ParamKind::vector))}});
  r.add({"deck", "contact", "A contact pair between two facet sets, or a surface in contact with itself (one list entry each).",
         {text("name", "pair name, used in messages and output", "contact<N>"),
          opt(text("master", "master facet set, auto (then give 'surfaces'), or a rigid obstacle {rigid: ...} (see "
                             "'describe rigid')", std::nullopt, ParamKind::any)),
          opt(text("slave", "slave facet set", std::nullopt)),
          opt(text("surface", "with self: true, the facet set in contact with itself", std::nullopt)),
          text("self", "self-contact of 'surface' (node_to_segment, one pass: every node is slave of the facets "
                       "that face it, its own and their neighbours excluded; mortar: the facets that face each other "
                       "coloured slave and master at each detection)", "false", ParamKind::boolean),
          opt(text("surfaces", "[A, B] with master: auto: the finer surface becomes slave; [A, B, C, ...]: a pair for every "
                               "two surfaces of different bodies within reach of each other (multi-body contact)",
                   std::nullopt, ParamKind::vector)),
          choice("discretization",
                 "node_to_segment (with node-to-edge and node-to-vertex), node_to_node (matching meshes), or mortar "
                 "(segment-based dual mortar: weighted gaps per slave node; 2D and 3D, every facet type incl. tri6 and quad8 "
                 "slaves (a transformed basis of non-negative functions), with friction; self-contact in 2D and on "
                 "tri3 and quad4 facets in 3D), or "
                 "segment_to_segment "
                 "(the slave facets' Gauss points projected on the master, gathered per slave node with dual weights; "
                 "2D and 3D, every facet type incl. tri6 and quad8, with friction)",
                 {"node_to_segment", "node_to_node", "mortar", "segment_to_segment"}, "node_to_segment"),
          number("passes", "2: each surface is also slave of the other (node_to_segment)", "1", 1, 2),
          choice("smoothing", "node_to_segment: hermite = in 2D a C1 cubic master curve through the nodes, in 3D "
                              "bicubic patches on quad4 master facets (normal continuous across nodes and edges; "
                              "kinks over 45 degrees stay sharp), none = faceted",
                 {"none", "hermite"}, "none"),
          opt(text("enforcement", "{method, penalty} (see 'describe enforcement')", std::nullopt, ParamKind::any)),
          opt(text("search", "{method, max_distance, update} (see 'describe search')", std::nullopt, ParamKind::any)),
          opt(text("friction", "{law, mu | bound, penalty, stick_predictor} (see 'describe friction'); omit for frictionless", std::nullopt,
                   ParamKind::any))}});
  r.add({"deck", "friction", "Friction on a contact pair (any enforcement). The tangential traction stays "
                             "within |t| <= bound: mu p (coulomb) or a constant (tresca); it sticks inside, slips on it.",
         {choice("law", "coulomb, tresca or none (frictionless)", {"coulomb", "tresca", "none"}, std::nullopt),
          opt(number("mu", "coulomb: the friction coefficient", std::nullopt, 0, INFINITY)),
          opt(number("bound", "tresca: the largest tangential traction", std::nullopt, 0, INFINITY)),
          text("penalty", "tangential penalty (traction per unit slip; with lagrange the tangential complementarity "
                          "constant), or auto = the normal penalty of the node (lagrange: 0.1 E/h for a node open at "
                          "the increment's start, E/h for one closed there); not with nitsche, whose tangential "
                          "parameter is its normal one",
               "auto", ParamKind::any),
          text("stick_predictor", "penalty and augmented_lagrangian: in the increment where the contact zone forms, a "
                                  "node that closes sticks while the normal statuses change, then slips freely (fewer "
                                  "Newton iterations; the same solution)",
               "true", ParamKind::boolean)}});
  r.add({"deck", "rigid", "A rigid analytic master surface; the body stays outside it (inside with inside: true). "
                          "It moves with {contact: <pair>, u: [...]} entries in a step's boundary list.",
         {choice("rigid", "shape (a cylinder is a circle in 2D)", {"plane", "cylinder", "sphere"}, std::nullopt),
          opt(text("point", "plane: a point of the plane", std::nullopt, ParamKind::vector)),
          opt(text("normal", "plane: its normal, pointing out of the obstacle towards the body", std::nullopt,
                   ParamKind::vector)),
          opt(text("center", "cylinder, sphere: the centre", std::nullopt, ParamKind::vector)),
          opt(number("radius", "cylinder, sphere: the radius", std::nullopt, 0, INFINITY, true)),
          opt(text("axis", "cylinder in 3D: its axis", std::nullopt, ParamKind::vector)),
          text("inside", "the body is inside the cylinder or sphere (a hole)", "false", ParamKind::boolean)}});
  r.add({"deck", "enforcement", "How the contact constraints are enforced.",
         {choice("method",
                 "lagrange: multipliers, semi-smooth Newton, exact non-penetration; augmented_lagrangian: penalty "
                 "with Uzawa updates of the multipliers until the gap tolerance is met; penalty: p = eps <-g>; "
                 "nitsche: Nitsche's method on segment_to_segment's integration points or on mortar's segments and "
                 "cells (the slave body's stress gives the pressure; elastic bodies, theta 0 at finite strain; with "
                 "friction the stress gives the tangential traction too)",
                 {"lagrange", "augmented_lagrangian", "penalty", "nitsche"}, "lagrange"),
          text("penalty", "penalty eps (pressure per unit penetration), or auto = penalty_factor * E / h_slave; also "
                          "the complementarity constant of lagrange", "auto", ParamKind::any),
          number("penalty_factor", "factor of the automatic penalty", "10", 0, INFINITY, true),
          number("max_flips", "status changes (open/closed, stick/slip) of a node in one increment before it is held in its status", "6", 1, 1000),
          text("gap_tolerance", "augmented_lagrangian: largest penetration accepted, or auto = 1e-3 x mean slave "
                                "facet size", "auto", ParamKind::any),
          number("max_uzawa", "augmented_lagrangian: Uzawa updates per increment before cutting back", "30", 1, 1000),
          text("gamma", "nitsche: gamma0 of the parameter gamma0 E / h (E the slave body's modulus, h the height of "
                        "the slave facet's cell over the facet, divided by the facet's order), or auto = 10", "auto", ParamKind::any),
          number("theta",
                 "nitsche: 1 symmetric (Cholesky), 0 incomplete, -1 skew-symmetric; at finite strain 0 (the default "
                 "there; 1 and -1 are refused)",
                 "1", -1, 1)}});
  r.add({"deck", "hardening", "Hardening of j2_plasticity (material key 'hardening').",
         {opt(text("isotropic", "{type: linear, H: ...} or {type: voce, saturation: ..., rate: ..., H: ...} (see "
                                "'describe isotropic_hardening')", std::nullopt, ParamKind::any)),
          opt(text("kinematic", "{H: ...}: linear kinematic hardening (Prager), back stress rate 2/3 H plastic "
                                "strain rate (see 'describe kinematic_hardening')", std::nullopt, ParamKind::any))}});
  r.add({"deck", "isotropic_hardening",
         "Isotropic hardening of j2_plasticity: sigma_y(alpha) = yield_stress + H alpha (linear), plus "
         "(saturation - yield_stress)(1 - exp(-rate alpha)) for voce; alpha the equivalent plastic strain.",
         {choice("type", "linear or voce", {"linear", "voce"}, std::nullopt),
          number("H", "linear hardening modulus (stress units)", "0", 0),
          opt(number("saturation", "voce: the yield stress approached at large alpha (without H); at least "
                                   "yield_stress", std::nullopt, 0, INFINITY, true)),
          opt(number("rate", "voce: saturation rate (1 / equivalent plastic strain)", std::nullopt, 0, INFINITY, true))}});
  r.add({"deck", "kinematic_hardening", "Linear kinematic hardening of j2_plasticity (Prager).",
         {number("H", "kinematic hardening modulus H_k (stress units)", std::nullopt, 0)}});
  r.add({"deck", "search", "Contact detection.",
         {choice("method", "global search: bucket_grid, bvh (AABB tree) or all_to_all (reference, slow)",
                 {"bucket_grid", "bvh", "all_to_all"}, "bucket_grid"),
          text("max_distance", "maximal detection distance, or auto = 2 x master facet size + 2 x largest nodal "
                               "motion of the increment's prediction", "auto", ParamKind::any),
          choice("update", "detection at the start of each increment, or at each Newton iteration",
                 {"increment", "iteration"}, "increment")}});
  r.add({"deck", "linear",
         "The linear solver of the Newton iterations: {type, rtol, forcing, options, partition, iterative_above, "
         "direct_factor_limit}, or "
         "just its type.",
         {choice("type", "the solver (see 'describe auto', 'describe gamg' etc.)", solvers, "auto"),
          number("rtol", "gamg, hypre, petsc, eigen_cg: relative residual of the Krylov iterations (with forcing: "
                         "adaptive, the tightest asked)", "1e-8", 0, 1, true, true),
          choice("forcing",
                 "Krylov solvers: adaptive asks each Newton iteration's solve for what that iteration can use "
                 "(Eisenstat & Walker: 1e-2 at first and while contact statuses change, then 0.9 (|R_k| / |R_k-1|)^2, down to "
                 "rtol); fixed asks rtol "
                 "of every solve; auto: adaptive on nonlinear models (contact, finite strain, material history), "
                 "fixed on linear ones",
                 {"auto", "adaptive", "fixed"}, "auto"),
          text("options", "gamg, hypre, mumps, petsc: raw PETSc options, e.g. \"-ksp_monitor -pc_gamg_threshold 0.02\"",
               "\"\""),
          choice("partition",
                 "under mpirun, how the cells are shared out between the ranks: rcb (recursive coordinate bisection of "
                 "their centroids) or ptscotch (PT-Scotch's cut of the cells' graph, through PETSc)",
                 {"rcb", "ptscotch"}, "rcb"),
          [] {
            ParamSpec p = number("iterative_above",
                                 "auto: a symmetric 3D system with more unknowns than this goes to algebraic multigrid "
                                 "(gamg; eigen_cg in a build without PETSc) instead of a factorization (CHOLMOD), and "
                                 "under mpirun to gamg instead of mumps",
                                 "200000", 1, 1e15);
            p.kind = ParamKind::integer;
            return p;
          }(),
          number("direct_factor_limit",
                 "auto, in a build with PETSc: a symmetric 3D system at or below iterative_above whose Cholesky factor "
                 "would hold more entries than this (CHOLMOD's symbolic analysis of the first pattern; 8 bytes each) "
                 "goes to gamg too (0: no limit)",
                 "5e7", 0, 1e18)}});
  r.add({"deck", "solver", "Newton-Raphson and linear solver settings.",
         {text("linear",
               "linear solver: a name (see 'describe cholmod' etc.) or {type, rtol, forcing, options, partition, "
               "iterative_above, direct_factor_limit} (see 'describe linear')",
               "auto", ParamKind::any),
          number("max_iterations", "Newton iterations per increment before cutting back", "25", 1, 1000),
          number("residual_tolerance", "relative residual |R| / max(|f_int|, |f_ext|)", "1e-8", 0, 1, true),
          number("absolute_tolerance", "absolute residual, force units (0: off)", "0", 0),
          number("energy_tolerance", "|du.R| relative to the first iteration's", "1e-16", 0, 1),
          text("line_search", "backtracking line search on the residual norm (with contact multipliers: only steps that "
                              "keep every contact status, and only for bodies with material history)",
               "true", ParamKind::boolean),
          number("penetration_step",
                 "contact with Lagrange multipliers or Nitsche: a Newton step that would push an open slave node "
                 "deeper than this many of its facet sizes into its master is shortened to about that (0: no limit)",
                 "0.5", 0),
          number("residual_growth",
                 "contact with Lagrange multipliers or Nitsche: a Newton step (otherwise full) that would raise the "
                 "residual norm more than this factor, or that inverts an element, is halved, at most six times (0: off)",
                 "0", 0),
          text("condense_contact",
               "solve Lagrange-multiplier contact systems without the multipliers (each closed constraint eliminates "
               "one DOF of its slave node; rows that couple several slave nodes, segment_to_segment and mortar, "
               "without their couplings, the step refined by GMRES), so that Cholesky or CG applies; frictional "
               "systems are solved whole",
               "true", ParamKind::boolean),
          text("predictor", "start each increment from the last one's displacement, extrapolated", "true",
               ParamKind::boolean),
          number("cutback_factor", "increment factor after a failed increment", "0.5", 0, 1, true, true),
          number("growth_factor", "increment factor after an easy increment", "1.5", 1, 10),
          number("easy_iterations", "an increment that converges in at most this many iterations is easy", "5", 0,
                 1000),
          number("stabilization",
                 "stabilization factor alpha (0: off): each free DOF gets the force alpha (D / dl) (u - u_p), u_p the "
                 "increment's predicted state, D the mean diagonal of the first stiffness matrix, dl the increment's "
                 "fraction of its step; for local instabilities (a snap of the discrete problem), reported per increment",
                 "0", 0, 1),
          text("pseudo_transient",
               "at a limit point (an increment cut back to its step's minimum), retry it with pseudo-transient "
               "continuation from the step's first increment size: Newton matrices shifted on their diagonal, the "
               "residual unchanged, so the state reached is the exact equilibrium",
               "true", ParamKind::boolean)}});
  r.add({"deck", "output", "Output settings.",
         {text("directory", "output directory (the command line's -o wins)", "results"),
          choice("vtu", "when to write ParaView files", {"every_increment", "last", "none"}, "every_increment"),
          choice("restart",
                 "every_step: a restart file restart_<step>.bin in the output directory after each step (signorini "
                 "run deck --restart FILE continues from it)",
                 {"none", "every_step"}, "none")}});
  r.add({"deck", "check", "A reference value compared with the result after the run; a failed check makes the run "
                          "exit with code 3.",
         {text("name", "what is checked", std::nullopt),
          choice("quantity",
                 "displacement (node nearest 'at'), reaction (sum over a node set), contact_pressure_max, "
                 "contact_pressure (at the slave node nearest 'at', reference coordinates), "
                 "contact_half_width (distance from 'at' along 'component' to the edge of the closed zone: midway "
                 "between the outermost closed slave node and the next open one; the mean of both sides if the zone "
                 "spans both) or contact_force (total, on the "
                 "slave side) of the contact pair 'pair', or contact_stick_half_width (friction: as contact_half_width "
                 "for the stick zone, between the outermost sticking node and the next slipping one)",
                 {"displacement", "reaction", "contact_pressure_max", "contact_pressure", "contact_half_width", "contact_force",
                  "contact_stick_half_width"},
                 std::nullopt),
          opt(text("pair", "contact pair name (contact quantities)", std::nullopt)),
          opt(text("at", "point (displacement, contact_pressure, half-widths)", std::nullopt, ParamKind::vector)),
          opt(text("set", "node set (reaction)", std::nullopt)),
          opt(choice("component", "component (not for contact_pressure_max, contact_pressure); r: for the contact half-widths in 3D, the radius of the zone around 'at' in the contact plane", {"x", "y", "z", "r"}, std::nullopt)),
          number("expected", "reference value", std::nullopt),
          number("tolerance", "relative tolerance", "0.01", 0, INFINITY, true),
          text("reference", "where the expected value comes from", "\"\"")}});
}

Registry default_registry() {
  Registry r;
  register_materials(r);
  register_linear_solvers(r);
  register_deck_sections(r);
  return r;
}

}  // namespace signorini

// The Model: everything the deck describes, as plain data. It owns the mesh, the bodies
// and the steps; the Analysis reads it and owns the iteration state.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "signorini/contact/contact_settings.hpp"
#include "signorini/fem/analysis_settings.hpp"
#include "signorini/fem/body.hpp"
#include "signorini/mesh/mesh.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini {

// A prescribed displacement component on a node set. Its value over the step goes
// linearly from `start` (or, if not given, the value the DOF has when the step begins)
// to `end`.
struct DirichletCondition {
  std::string set;
  int component = 0;
  std::optional<Real> start;
  Real end = 0;
  std::string where;  // deck location
  bool hold = false;  // held at the value the step begins with (`hold` in the deck; end unused)
};

enum class LoadKind { nodal_force, traction, pressure, body_force, centrifugal, obstacle_force, body_moment };

// A centrifugal body force rho omega^2 (X - o - ((X - o) . a) a) per unit reference volume
// (a dead load on the reference configuration: small rotations of the body).
struct Centrifugal {
  Real density = 0, omega = 0;
  Vec3 axis = Vec3::UnitZ();  // unit; 2D: z (out of plane); axisymmetric: the y axis
  Vec3 origin = Vec3::Zero();
};

// A load, ramped over its step from the value it had at the end of the previous step
// (loads not listed in a step are removed, ramped to zero).
struct Load {
  LoadKind kind = LoadKind::nodal_force;
  std::string set;        // node set, facet set, body name (body force, body moment) or contact pair (obstacle force)
  Vec3 vector = Vec3::Zero();  // total force, traction, or body force per unit volume
  Real pressure = 0;
  // obstacle_force, body_moment: the moment (plane problems: about z, its z component; 3D: a
  // fixed spatial vector, geometry/rotation.hpp for its work on the angles)
  std::optional<Vec3> moment;
  bool obstacle_translations = true;  // obstacle_force: a force is given (its translations are then free)
  Centrifugal centrifugal;
  std::string where;
};

// Prescribed displacement components of a rigid obstacle (absent: not prescribed), and its
// rotation, ramped over the step like Dirichlet values from where the obstacle is when the
// step begins. Translations neither prescribed nor loaded by an obstacle force are held where
// they are; the rotation likewise, unless the load has a moment.
struct ObstacleMotion {
  std::string pair;
  std::optional<Real> u[3];
  // Plane problems: the angle about z (radians, counter-clockwise) as the z component; 3D: the
  // rotation vector (axis times angle).
  std::optional<Vec3> rotation;
};

// The rotation a meshed rigid body turns to about its reference node (plane problems: the
// angle about z as the z component; 3D: the rotation vector), each component ramped over the
// step from the value it has when the step begins.
struct BodyTurn {
  std::string body;
  Vec3 rotation = Vec3::Zero();
};

// The angles of a rotation with `n` of them (1: plane problems, about z; 3: a rotation vector)
// as components of a Vec3: angle i is component rotation_component(i, n).
inline int rotation_component(int i, int n) { return n == 1 ? 2 : i; }

struct Step {
  std::string name;
  Real initial_increment = 1.0;  // fractions of the step
  Real min_increment = 1e-5;
  Real max_increment = 1.0;
  int max_increments = 10000;
  Real duration = 1;             // the step's time (key `time`), for rate-dependent materials
  std::vector<DirichletCondition> dirichlet;
  std::vector<ObstacleMotion> obstacles;
  std::vector<BodyTurn> body_turns;
  std::vector<Load> loads;
};

struct NewtonSettings {
  int max_iterations = 25;
  Real residual_tolerance = 1e-8;     // relative to the force scale of the problem
  Real absolute_tolerance = 0;        // in force units; 0: only the relative test
  Real energy_tolerance = 1e-16;      // |du . R| relative to the first iteration's
  bool line_search = true;
  // Contact: the largest growth of an open slave node's penetration in one Newton step, in
  // facet sizes (Lagrange multipliers and Nitsche; 0: no limit). Analysis::line_search.
  Real penetration_step = 0.5;
  // The full steps of the semi-smooth Newton method (Lagrange multipliers, Nitsche): a step
  // that would raise the residual norm more than this factor, or that inverts an element, is
  // halved, at most six times (0: off). Analysis::line_search.
  Real residual_growth = 0;
  bool predictor = true;              // extrapolate the last increment's displacement
  bool condense_contact = true;       // eliminate contact multipliers from the linear solve
  Real cutback_factor = 0.5;
  Real growth_factor = 1.5;
  int easy_iterations = 5;            // grow the increment after convergence in <= this
  // Stabilization factor alpha (0: off): every free displacement DOF i gets the force
  // alpha (D / dl) (u_i - u_i,p), u_p the increment's predicted state, D the mean diagonal of
  // the first stiffness matrix, dl the increment as a fraction of its step; it grows as the
  // increment is cut back (analysis.cpp).
  Real stabilization = 0;
  // At a limit point (the increment cut back to its step's minimum), retry with pseudo-transient
  // continuation from the step's first increment size (analysis.cpp, run_steps).
  bool pseudo_transient = true;
};

struct OutputSettings {
  std::string directory = "results";
  std::string vtu = "every_increment";  // every_increment, last, none
  std::string restart = "none";         // every_step: restart_<step>.bin after each step
};

// A reference value to compare with after the run (deck `checks:`).
struct Check {
  std::string name;
  std::string kind;      // displacement, reaction, contact_pressure_max, contact_half_width, contact_force
  std::string set;
  std::string pair;      // contact quantities
  Vec3 point = Vec3::Zero();
  static constexpr int radial = 3;  // contact half-widths in 3D: a radius in the contact plane
  int component = 0;                // 0, 1, 2 or radial
  Real expected = 0;
  Real tolerance = 0.01;  // relative
  std::string reference;  // where the expected value comes from
  std::string where;
};

struct Model {
  std::string title;
  std::string deck_path;
  AnalysisSettings settings;
  Mesh mesh;
  std::vector<std::unique_ptr<Body>> bodies;
  std::vector<Step> steps;
  std::vector<ContactPairSettings> contacts;
  NewtonSettings newton;
  LinearSolverSettings linear_solver;
  // Where the deck names the linear solver (file:line of solver.linear), for the errors about
  // it found once the model is set up; empty when the deck does not name one.
  std::string linear_solver_where;
  OutputSettings output;
  std::vector<Check> checks;
};

// Why the model's linear systems are unsymmetric (each reason naming its contact pair or step):
// friction, Nitsche's method with theta other than 1, follower pressure under finite strain, a
// moment in 3D. Empty when they are symmetric (Lagrange multipliers aside: their saddle point
// is condensed to a symmetric system). The Analysis' own test is Analysis::symmetric_solves.
std::vector<std::string> unsymmetric_tangent_reasons(const Model& model);
// The refusal of a solver for symmetric systems only (is_symmetric_only_solver) named for a
// model whose systems are unsymmetric (by unsymmetric_tangent_reasons, or `unsymmetric`: the
// Analysis' own verdict), naming the reasons; empty when there is none to make. Until session 64 such
// a solver solved the tangent's symmetric part (one triangle read): examples/friction_block with
// cholmod took 73 Newton iterations against 28, examples/cattaneo_cylinder gave up after its
// cutbacks, with eigen_ldlt it ran past 5 minutes.
std::string symmetric_solver_refusal(const Model& model, bool unsymmetric = false);

}  // namespace signorini

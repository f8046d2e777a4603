// What the deck says about one contact pair: the surfaces, the discretization, the
// enforcement method and the search options. Plain data, validated by the deck reader.
#pragma once
#include <string>

#include "signorini/core/types.hpp"

namespace signorini {

// A rigid analytic master surface: the body stays outside it (or inside, for a hole).
struct RigidObstacle {
  std::string shape;             // plane, cylinder (a circle in 2D), sphere
  Vec3 point = Vec3::Zero();     // plane: a point; cylinder, sphere: the centre
  Vec3 normal = Vec3::UnitY();   // plane: unit normal pointing out of the obstacle
  Vec3 axis = Vec3::UnitZ();     // cylinder in 3D: unit axis
  Real radius = 0;
  bool inside = false;           // the body is inside the cylinder or sphere (a hole)
};

// Nitsche's method: the default gamma0 of its parameter gamma0 E / h (docs/contact.md).
constexpr Real kNitscheGamma = 10;

struct ContactPairSettings {
  std::string name;
  std::string master;                             // facet set (empty for a rigid obstacle)
  bool rigid = false;
  RigidObstacle obstacle;
  bool turns = false;                             // rigid obstacle (plane problems): its angle is an unknown (a step
                                                  // prescribes it or loads it by a moment)
  std::string slave;                              // facet set
  bool self = false;                              // self-contact: master and slave are one surface
  std::string discretization = "node_to_segment"; // node_to_segment, node_to_node
  std::string smoothing = "none";                 // none, hermite (2D: C1 master curve through the nodes)
  int passes = 1;                                 // 2: each surface is also slave of the other
  std::string method = "lagrange";                // lagrange (semi-smooth Newton), augmented_lagrangian, penalty, nitsche
  Real penalty = 0;                               // 0: automatic, penalty_factor * E / h
  Real penalty_factor = 10;
  std::string search = "bucket_grid";             // bucket_grid, bvh, all_to_all
  Real max_distance = 0;                          // 0: automatic
  std::string update = "increment";               // increment, iteration
  int max_flips = 6;                              // status changes of a node in one increment before it is frozen
  Real gap_tolerance = 0;                         // augmented Lagrangian: 0 = 1e-3 x mean slave facet size
  int max_uzawa = 30;                             // augmented Lagrangian: updates per increment
  Real nitsche_gamma = 0;                         // nitsche: gamma0 of the parameter gamma0 E / h (0: kNitscheGamma)
  int nitsche_theta = 1;                          // nitsche: 1 symmetric, 0 incomplete, -1 skew-symmetric
  bool nitsche_exact_tangent = false;             // nitsche: the whole P hess g in the matrix (tests; enforcement.cpp)
  std::string friction = "none";                  // friction law: none, coulomb, tresca
  Real friction_parameter = 0;                    // coulomb: mu; tresca: the bound on |t|
  Real tangential_penalty = 0;                    // 0: automatic, the normal penalty of the node
  bool stick_predictor = true;                    // penalty, augmented Lagrangian: ContactInterface::end_stick_predictor
  std::string where;                              // deck location
};

}  // namespace signorini

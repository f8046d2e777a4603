// examples/tube_crush_3d on its own mesh (27-node hexahedra, 40 and 34 cells along the wall)
// against examples/tube_crush: the 3D slice gives the plane strain ring's answer per unit
// depth (tests/tube_slice.hpp has the checks).
#include "tube_slice.hpp"

TEST(SelfContact, TubeSliceIn3DFoldsAsThePlaneStrainTubeOnTheExampleMesh) {
  signorini::test::compare_tube_slice_with_plane_strain("", 3);
}

// The tube's fold as dual mortar (tests/tube_slice.hpp) on the example's own mesh (quadratic
// cells, line3 facets on the transformed basis, 40 and 34 along the wall) with each method,
// and on linear cells with the penalty systems. The augmented Lagrangian accepts 1e-3 of the
// largest facet as penetration (0.44 and 0.75 mm facets); penalty's penetration softens the
// fold, so its bar force and peak pressure are lower (within 10 % and 25 %), and is that of its
// automatic stiffness, 10 E/h = 230 MPa/mm against fold pressures of 3 E (below 0.15 mm).
// Measured (one run, 34 s): Lagrange -0.246 %, peak 36.3 against 37.1 MPa, the same closure at
// first touch (19.28 mm), 24 increments against 26; the augmented Lagrangian -0.252 % and
// +0.014 % (linear cells), 68-69 increments (cut back at the first touch); penalty -3.9 % and
// -7.6 %, peaks -20 % and -13 %, penetration 0.106 mm.
TEST(SelfContact, TubeFoldAsMortarOnTheExampleMesh) {
  signorini::test::compare_mortar_fold("", "lagrange", 5e-3, 1e-8, 0.05);
  signorini::test::compare_mortar_fold("", "augmented_lagrangian", 5e-3, 4.4e-4, 0.05);
  signorini::test::compare_mortar_fold("order: 1, nu: 24, nl: 20", "augmented_lagrangian", 5e-3, 7.5e-4, 0.05);
  signorini::test::compare_mortar_fold("", "penalty", 0.1, 0.15, 0.25);
  signorini::test::compare_mortar_fold("order: 1, nu: 24, nl: 20", "penalty", 0.1, 0.15, 0.25);
}

// examples/tube_crush_3d on its own mesh (27-node hexahedra, 40 and 34 cells along the wall)
// against examples/tube_crush: the 3D slice gives the plane strain ring's answer per unit
// depth (tests/tube_slice.hpp has the checks).
#include "tube_slice.hpp"

TEST(SelfContact, TubeSliceIn3DFoldsAsThePlaneStrainTubeOnTheExampleMesh) {
  signorini::test::compare_tube_slice_with_plane_strain("", 3);
}

// The tube's fold as dual mortar (tests/tube_slice.hpp) on the example's own mesh (quadratic
// cells, line3 facets on the transformed basis, 40 and 34 along the wall; the augmented
// Lagrangian accepts 1e-3 of the largest facet, 0.44 mm, as penetration), and with penalty on
// both meshes: penalty's penetration softens the fold, so its bar force is lower (within 5 %)
// and its penetration is that of its automatic stiffness (below 0.1 mm, a tenth of the wall).
// Measured: the augmented Lagrangian's bar force +0.008 %, peak pressure 36.7 against 37.1 MPa
// on 10 closed nodes; penalty -1.7 % and -3.4 % (linear cells), peaks -7 % and +10 %.
TEST(SelfContact, TubeFoldAsMortarOnTheExampleMesh) {
  signorini::test::compare_mortar_fold("", "augmented_lagrangian", 5e-3, 4.4e-4, 0.05);
  signorini::test::compare_mortar_fold("", "penalty", 5e-2, 0.1, 0.15);
  signorini::test::compare_mortar_fold("order: 1, nu: 24, nl: 20", "penalty", 5e-2, 0.1, 0.25);
}

// examples/tube_crush_3d on its own mesh (27-node hexahedra, 40 and 34 cells along the wall)
// against examples/tube_crush: the 3D slice gives the plane strain ring's answer per unit
// depth (tests/tube_slice.hpp has the checks).
#include "tube_slice.hpp"

TEST(SelfContact, TubeSliceIn3DFoldsAsThePlaneStrainTubeOnTheExampleMesh) {
  signorini::test::compare_tube_slice_with_plane_strain("", 3);
}

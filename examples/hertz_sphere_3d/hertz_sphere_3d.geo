// Hertz contact of a sphere on a block in 3D, quarter model (x >= 0, y >= 0), tetrahedra
// (order 1: tet4, 2: tet10).
// Sphere of radius R centred at (0, 0, R), its lower half; block [0, W]^2 x [-H, 0].
SetFactory("OpenCASCADE");
DefineConstant[ R = 1, W = 1.5, H = 1.5, hc = 0.02, hf = 0.3, zone = 0.15, order = 1 ];
Box(1) = {0, 0, -H, W, W, H};
Sphere(2) = {0, 0, R, R};
Box(3) = {0, 0, 0, R, R, R};
BooleanIntersection(4) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
eps = 1e-6;
blockTop() = Surface In BoundingBox{-eps, -eps, -eps, W + eps, W + eps, eps};
blockBottom() = Surface In BoundingBox{-eps, -eps, -H - eps, W + eps, W + eps, -H + eps};
blockX0() = Surface In BoundingBox{-eps, -eps, -H - eps, eps, W + eps, eps};
blockY0() = Surface In BoundingBox{-eps, -eps, -H - eps, W + eps, eps, eps};
sphereTop() = Surface In BoundingBox{-eps, -eps, R - eps, R + eps, R + eps, R + eps};
sphereX0() = Surface In BoundingBox{-eps, -eps, -eps, eps, R + eps, R + eps};
sphereY0() = Surface In BoundingBox{-eps, -eps, -eps, R + eps, eps, R + eps};
sphereAll() = Boundary{ Volume{4}; };
sphereCurved() = sphereAll();
sphereCurved() -= {sphereTop(), sphereX0(), sphereY0()};
Field[1] = Distance;
Field[1].PointsList = {Point In BoundingBox{-eps, -eps, -eps, eps, eps, eps}};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = hf;
Field[2].DistMin = zone;
Field[2].DistMax = 6 * zone;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.ElementOrder = order;  // 2: tet10, mid-side nodes on the sphere
Physical Volume("Block") = {1};
Physical Volume("Sphere") = {4};
Physical Surface("BlockTop") = {blockTop()};
Physical Surface("BlockBottom") = {blockBottom()};
Physical Surface("BlockX0") = {blockX0()};
Physical Surface("BlockY0") = {blockY0()};
Physical Surface("SphereSurface") = {sphereCurved()};
Physical Surface("SphereTop") = {sphereTop()};
Physical Surface("SphereX0") = {sphereX0()};
Physical Surface("SphereY0") = {sphereY0()};

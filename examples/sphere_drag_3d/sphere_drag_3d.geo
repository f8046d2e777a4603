// A sphere dragged across a block in 3D (examples/cattaneo_sphere_3d's geometry), half model
// (y >= 0: the motion along x keeps the plane y = 0 a symmetry plane), tetrahedra; the refined
// box around the contact disc stretched by `drag` along +x to cover the path.
// Sphere of radius R centred at (0, 0, R), its lower half; block [-W, W] x [0, W] x [-H, 0].
// Element size hc in a thin box around the contact disc (|x| < 1.4 a0, y < 1.4 a0,
// |z| < 0.25 a0, a0 = 0.1 the Hertz radius of the deck), growing to hf away from it.
SetFactory("OpenCASCADE");
DefineConstant[ R = 1, W = 1.5, H = 1.5, hc = 0.02, hf = 0.3, a0 = 0.1, drag = 0.2 ];
Box(1) = {-W, 0, -H, 2 * W, W, H};
Sphere(2) = {0, 0, R, R};
Box(3) = {-R, 0, 0, 2 * R, R, R};
BooleanIntersection(4) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
eps = 1e-6;
blockTop() = Surface In BoundingBox{-W - eps, -eps, -eps, W + eps, W + eps, eps};
blockBottom() = Surface In BoundingBox{-W - eps, -eps, -H - eps, W + eps, W + eps, -H + eps};
blockY0() = Surface In BoundingBox{-W - eps, -eps, -H - eps, W + eps, eps, eps};
sphereTop() = Surface In BoundingBox{-R - eps, -eps, R - eps, R + eps, R + eps, R + eps};
sphereY0() = Surface In BoundingBox{-R - eps, -eps, -eps, R + eps, eps, R + eps};
sphereAll() = Boundary{ Volume{4}; };
sphereCurved() = sphereAll();
sphereCurved() -= {sphereTop(), sphereY0()};
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = hf;
Field[1].XMin = -1.4 * a0;
Field[1].XMax = 1.4 * a0 + drag;
Field[1].YMin = -1;
Field[1].YMax = 1.4 * a0;
Field[1].ZMin = -0.25 * a0;
Field[1].ZMax = 0.25 * a0;
Field[1].Thickness = 3 * a0;
Field[2] = Distance;
Field[2].PointsList = {Point In BoundingBox{-eps, -eps, -eps, eps, eps, eps}};
Field[3] = Threshold;
Field[3].InField = 2;
Field[3].SizeMin = 4 * hc;
Field[3].SizeMax = hf;
Field[3].DistMin = 2 * a0;
Field[3].DistMax = 10 * a0;
Field[4] = Min;
Field[4].FieldsList = {1, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Volume("Block") = {1};
Physical Volume("Sphere") = {4};
Physical Surface("BlockTop") = {blockTop()};
Physical Surface("BlockBottom") = {blockBottom()};
Physical Surface("BlockY0") = {blockY0()};
Physical Surface("SphereSurface") = {sphereCurved()};
Physical Surface("SphereTop") = {sphereTop()};
Physical Surface("SphereY0") = {sphereY0()};

// An elastic block [-W, W]^2 x [-H, 0] under a rigid ball that rolls from the origin along
// the direction (cos 30 deg, sin 30 deg, 0): tetrahedra of size hc in a box around the path,
// growing to hf away from it.
SetFactory("OpenCASCADE");
DefineConstant[ W = 4, H = 4, hc = 0.2, hf = 1.2 ];
Box(1) = {-W, -W, -H, 2 * W, 2 * W, H};
eps = 1e-6;
Physical Volume("Block") = {1};
Physical Surface("Top") = {Surface In BoundingBox{-W - eps, -W - eps, -eps, W + eps, W + eps, eps}};
Physical Surface("Bottom") = {Surface In BoundingBox{-W - eps, -W - eps, -H - eps, W + eps, W + eps, -H + eps}};
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = hf;
Field[1].XMin = -1.0;
Field[1].XMax = 1.9;
Field[1].YMin = -1.0;
Field[1].YMax = 1.5;
Field[1].ZMin = -0.9;
Field[1].ZMax = 0.1;
Field[1].Thickness = 2.0;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// Brinell indentation, axisymmetric (x = r, y = axial): the half-space is the block
// [0, W] x [-H, 0]; quadratic quadrilaterals of size hc within `zone` of the axis point at the
// surface, growing to hf. The indenter is a rigid sphere (in the deck).
DefineConstant[ W = 8, H = 8, hc = 0.025, hf = 1.0, zone = 0.7, order = 2 ];
Point(1) = {0, -H, 0, hf};
Point(2) = {W, -H, 0, hf};
Point(3) = {W, 0, 0, hf};
Point(4) = {0, 0, 0, hc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {4};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = hf;
Field[2].DistMin = zone;
Field[2].DistMax = 12 * zone;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("Block") = {1};
Physical Curve("Bottom") = {1};
Physical Curve("Outer") = {2};
Physical Curve("Top") = {3};
Physical Curve("Axis") = {4};

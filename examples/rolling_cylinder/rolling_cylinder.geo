// An elastic block [-L, L] x [-H, 0] (plane strain) under a rigid roller: quadrilaterals of
// size hc in the strip x in [x0, x1], y in [-depth, 0] where the roller presses and rolls,
// growing to hf away from it.
DefineConstant[ L = 20, H = 20, hc = 0.05, hf = 2.5, x0 = -2.5, x1 = 7.5, depth = 1.5 ];
Point(1) = {-L, -H, 0, hf};
Point(2) = {L, -H, 0, hf};
Point(3) = {L, 0, 0, hf};
Point(4) = {-L, 0, 0, hf};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = hf;
Field[1].XMin = x0;
Field[1].XMax = x1;
Field[1].YMin = -depth;
Field[1].YMax = 1;
Field[1].Thickness = 4;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Physical Surface("Block") = {1};
Physical Curve("Bottom") = {1};
Physical Curve("Top") = {3};

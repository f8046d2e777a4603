// A disk with a blade held in a dovetail slot, plane strain, in the (x, y) plane; the disk
// spins about the z axis. Units mm. The blade stands along +y; the model is the quarter
// x >= 0, y >= 0 (symmetry x = 0 through the blade and the slot; y = 0 through the disk: a disk
// with two blades, each half-sector a mirror image). Disk: the annulus r in [ri, ro] with the
// slot cut at its top. Blade (half): a root whose 45-degree flank x + y = 272 bears on the
// slot's flank, a shank through the slot's neck (1 mm clearance) and a block standing for the
// airfoil. The flanks touch at the start (no gap, no interference); the slot's bottom is 4 mm
// below the blade's. Quadratic quadrilaterals of size hc near the flanks, hf away from them.
DefineConstant[ ri = 150, ro = 280, hc = 0.6, hf = 8, order = 2 ];
// Disk
Point(1) = {0, 0, 0, hf};
Point(2) = {ri, 0, 0, hf};
Point(3) = {ro, 0, 0, hf};
Point(4) = {11, Sqrt(ro * ro - 121), 0, hc};
Point(5) = {11, 261, 0, hc};
Point(6) = {22, 250, 0, hc};
Point(7) = {22, 248, 0, hc};
Point(8) = {0, 248, 0, hc};
Point(9) = {0, ri, 0, hf};
Line(1) = {2, 3};            // y = 0
Circle(2) = {3, 1, 4};       // outer rim
Line(3) = {4, 5};            // slot neck wall
Line(4) = {5, 6};            // slot flank (x + y = 272)
Line(5) = {6, 7};
Line(6) = {7, 8};            // slot bottom
Line(7) = {8, 9};            // x = 0
Circle(8) = {9, 1, 2};       // bore
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
// Blade
Point(11) = {0, 252, 0, hc};
Point(12) = {20, 252, 0, hc};
Point(13) = {10, 262, 0, hc};
Point(14) = {10, 290, 0, hc};
Point(15) = {25, 290, 0, hf / 2};
Point(16) = {25, 350, 0, hf};
Point(17) = {0, 350, 0, hf};
Line(11) = {11, 12};         // root bottom
Line(12) = {12, 13};         // blade flank (x + y = 272)
Line(13) = {13, 14};         // shank
Line(14) = {14, 15};
Line(15) = {15, 16};
Line(16) = {16, 17};
Line(17) = {17, 11};         // x = 0
Curve Loop(2) = {11, 12, 13, 14, 15, 16, 17};
Plane Surface(2) = {2};
Field[1] = Distance;
Field[1].CurvesList = {4, 12};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = hf;
Field[2].DistMin = 3;
Field[2].DistMax = 60;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("Disk") = {1};
Physical Surface("Blade") = {2};
Physical Curve("DiskSymX") = {7};
Physical Curve("DiskSymY") = {1};
Physical Curve("BladeSymX") = {17};
Physical Curve("SlotFlank") = {4};
Physical Curve("BladeFlank") = {12};

// The disk-blade dovetail of examples/long/dovetail as a 3D sector: the same quarter (x >= 0,
// y >= 0: symmetry x = 0 through the blade and the slot, y = 0 through the disk; the disk
// spins about the z axis) extruded along z by half the disk's thickness, `half` (symmetry at
// z = 0, the mid-plane; the face z = half free), in `layers` layers of hexahedra. The flank
// pressure is then no longer uniform through the thickness: the free face lets the root
// spread. Units mm.
DefineConstant[ ri = 150, ro = 280, hc = 1.5, hf = 10, order = 1, half = 15, layers = 5 ];
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
disk[] = Extrude {0, 0, half} { Surface{1}; Layers{layers}; Recombine; };
blade[] = Extrude {0, 0, half} { Surface{2}; Layers{layers}; Recombine; };
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
eps = 1e-3;
// The 2D curves' extrusions, by bounding boxes: the disk's x = 0 face below the slot, its y = 0
// face, the blade's x = 0 face, and the two flanks (x + y = 272, the slot's for x in [11, 22],
// the blade's for x in [10, 20]).
Physical Volume("Disk") = {disk[1]};
Physical Volume("Blade") = {blade[1]};
Physical Surface("DiskSymX") = {Surface In BoundingBox{-eps, ri - eps, -eps, eps, 248 + eps, half + eps}};
Physical Surface("DiskSymY") = {Surface In BoundingBox{ri - eps, -eps, -eps, ro + eps, eps, half + eps}};
Physical Surface("BladeSymX") = {Surface In BoundingBox{-eps, 252 - eps, -eps, eps, 350 + eps, half + eps}};
Physical Surface("SlotFlank") = {Surface In BoundingBox{11 - eps, 250 - eps, -eps, 22 + eps, 261 + eps, half + eps}};
Physical Surface("BladeFlank") = {Surface In BoundingBox{10 - eps, 252 - eps, -eps, 20 + eps, 262 + eps, half + eps}};
Physical Surface("DiskMid") = {Surface In BoundingBox{-eps, -eps, -eps, ro + eps, ro + eps, eps}};
Physical Surface("BladeMid") = {Surface In BoundingBox{-eps, 252 - eps, -eps, 25 + eps, 350 + eps, eps}};

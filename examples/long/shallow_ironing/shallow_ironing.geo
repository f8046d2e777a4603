// Shallow ironing (VALIDATION.md sec. 4), plane strain, SI units: a slab 12 x 4 and an
// indenter 1.2 wide with straight sides 0.9 high and a circular bottom arc of radius 0.75
// (sagitta 0.3), its left edge at x = 0.2 and its lowest point 0.2 above the slab.
// Structured quadrilaterals: slab nx x ny, indenter mx x my.
DefineConstant[ nx = 120, ny = 30, mx = 12, my = 6 ];
Point(1) = {0, 0, 0};
Point(2) = {12, 0, 0};
Point(3) = {12, 4, 0};
Point(4) = {0, 4, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1};
Point(11) = {0.2, 4.5, 0};
Point(12) = {1.4, 4.5, 0};
Point(13) = {1.4, 5.4, 0};
Point(14) = {0.2, 5.4, 0};
Point(15) = {0.8, 4.95, 0};
Circle(11) = {11, 15, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};
Transfinite Curve{11, 13} = mx + 1;
Transfinite Curve{12, 14} = my + 1;
Transfinite Surface{2} = {11, 12, 13, 14};
Recombine Surface{1, 2};
Physical Surface("Slab") = {1};
Physical Surface("Indenter") = {2};
Physical Curve("SlabBottom") = {1};
Physical Curve("SlabTop") = {3};
Physical Curve("IndenterArc") = {11};
Physical Curve("IndenterTop") = {13};
Physical Curve("IndenterSurface") = {14, 11, 12};  // the arc and both sides (master, or mortar slave)

// A tube (ring) of mean radius R and wall thickness t, the right half (x >= 0; symmetry at
// x = 0), centred at the origin; structured quadratic quadrilaterals, nt through the wall,
// nu on the upper quarter of the circumference and nl on the lower one (different, so that
// the two halves of the inner wall meet with non-matching nodes). The symmetry plane y = 0
// cuts the wall at Mid.
DefineConstant[ R = 10, t = 1, nt = 3, nu = 40, nl = 34, order = 2 ];
ri = R - t / 2;
ro = R + t / 2;
Point(1) = {0, 0, 0};
Point(2) = {0, -ri, 0};
Point(3) = {ri, 0, 0};
Point(4) = {0, ri, 0};
Point(5) = {0, -ro, 0};
Point(6) = {ro, 0, 0};
Point(7) = {0, ro, 0};
Circle(1) = {2, 1, 3};   // inner, lower quarter
Circle(2) = {3, 1, 4};   // inner, upper quarter
Circle(3) = {5, 1, 6};   // outer, lower quarter
Circle(4) = {6, 1, 7};   // outer, upper quarter
Line(5) = {2, 5};        // x = 0, bottom
Line(6) = {3, 6};        // y = 0
Line(7) = {4, 7};        // x = 0, top
Curve Loop(1) = {5, 3, -6, -1};
Plane Surface(1) = {1};
Curve Loop(2) = {6, 4, -7, -2};
Plane Surface(2) = {2};
Transfinite Curve{1, 3} = nl + 1;
Transfinite Curve{2, 4} = nu + 1;
Transfinite Curve{5, 6, 7} = nt + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("Tube") = {1, 2};
Physical Curve("Inner") = {1, 2};
Physical Curve("Outer") = {3, 4};
Physical Curve("Sym") = {5, 7};
Physical Curve("Mid") = {6};

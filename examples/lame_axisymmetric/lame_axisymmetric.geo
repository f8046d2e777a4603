// Axisymmetric slice of a thick-walled cylinder: r from a to b, z from 0 to t (x = r, y = z).
DefineConstant[ a = 0.1, b = 0.2, t = 0.02, nr = 16, order = 2 ];
Point(1) = {a, 0, 0}; Point(2) = {b, 0, 0}; Point(3) = {b, t, 0}; Point(4) = {a, t, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nr + 1;
Transfinite Curve{2, 4} = 3;
Transfinite Surface{1};
Recombine Surface{1};
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 1;
Physical Surface("Wall") = {1};
Physical Curve("Bottom") = {1};
Physical Curve("Outer") = {2};
Physical Curve("Top") = {3};
Physical Curve("Inner") = {4};

// A unit cube of hexahedra (one eighth of a bar, with symmetry planes x = 0, y = 0, z = 0).
DefineConstant[ n = 2 ];
Point(1) = {0, 0, 0, 1};
Point(2) = {1, 0, 0, 1};
Line(1) = {1, 2};
Transfinite Curve{1} = n + 1;
a[] = Extrude {0, 1, 0} { Curve{1}; Layers{n}; Recombine; };
b[] = Extrude {0, 0, 1} { Surface{a[1]}; Layers{n}; Recombine; };
Physical Volume("Bar") = {b[1]};
Physical Surface("ZMin") = {a[1]};
Physical Surface("ZMax") = {b[0]};
Physical Surface("YMin") = {b[2]};
Physical Surface("XMax") = {b[3]};
Physical Surface("YMax") = {b[4]};
Physical Surface("XMin") = {b[5]};

// examples/tube_crush's ring (mean radius R, wall thickness t, the right half, x >= 0, its
// upper and lower quarters meshed with nu and nl cells along the wall, nt through it),
// extruded along z by one layer of depth `depth` into hexahedra (27 nodes: quad9 faces): a
// slice of the tube whose faces z = 0 and z = depth are held in z, so that it deforms as the
// plane strain ring does.
DefineConstant[ R = 10, t = 1, nt = 3, nu = 40, nl = 34, order = 2, depth = 1 ];
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
Extrude {0, 0, depth} { Surface{1, 2}; Layers{1}; Recombine; }
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
eps = 1e-6;
Physical Volume("Tube") = {Volume{:}};
// The walls: the extruded circles (inner radius ri, outer ro), found by their bounding boxes.
inner() = Surface In BoundingBox{-eps, -ri - eps, -eps, ri + eps, ri + eps, depth + eps};
inner() -= Surface In BoundingBox{-eps, -ri - eps, -eps, eps, ri + eps, depth + eps};
inner() -= Surface In BoundingBox{-eps, -eps, -eps, ri + eps, eps, depth + eps};
front() = Surface In BoundingBox{-eps, -ro - eps, -eps, ro + eps, ro + eps, eps};
back() = Surface In BoundingBox{-eps, -ro - eps, depth - eps, ro + eps, ro + eps, depth + eps};
sym() = Surface In BoundingBox{-eps, -ro - eps, -eps, eps, ro + eps, depth + eps};
mid() = Surface In BoundingBox{ri - eps, -eps, -eps, ro + eps, eps, depth + eps};
all() = Surface{:};
outer() = all();
outer() -= {inner(), front(), back(), sym(), mid(), 1, 2};
Physical Surface("Inner") = {inner()};
Physical Surface("Outer") = {outer()};
Physical Surface("Sym") = {sym()};
Physical Surface("Mid") = {mid()};
Physical Surface("Faces") = {front(), back()};

// A cantilever of length L and square section H x W, hexahedra by extrusion.
DefineConstant[ L = 10, H = 1, W = 1, nl = 20, nh = 4, nw = 4, order = 2 ];
Point(1) = {0, 0, 0, 1};
Point(2) = {0, H, 0, 1};
Line(1) = {1, 2};
Transfinite Curve{1} = nh + 1;
s[] = Extrude {0, 0, W} { Curve{1}; Layers{nw}; Recombine; };
v[] = Extrude {L, 0, 0} { Surface{s[1]}; Layers{nl}; Recombine; };
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 1;
Physical Volume("Beam") = {v[1]};
Physical Surface("Clamped") = {s[1]};
Physical Surface("Tip") = {v[0]};

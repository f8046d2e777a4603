// A Neo-Hookean block [0.5, 1.5] x [0, 0.5] on a foundation [-1, 6] x [-0.5, 0] whose top is
// finely meshed (facets 0.1 long): the block slides 3 = 30 facets in one increment.
DefineConstant[ nf = 70, nb = 20 ];
Point(1) = {-1, -0.5, 0}; Point(2) = {6, -0.5, 0}; Point(3) = {6, 0, 0}; Point(4) = {-1, 0, 0};
Point(5) = {0.53, 0, 0}; Point(6) = {1.53, 0, 0}; Point(7) = {1.53, 0.5, 0}; Point(8) = {0.53, 0.5, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{1, 3} = nf + 1; Transfinite Curve{2, 4} = 6;
Transfinite Curve{5, 7} = nb + 1; Transfinite Curve{6, 8} = 11;
Transfinite Surface{1, 2}; Recombine Surface{1, 2};
Physical Surface("Foundation") = {1}; Physical Surface("Block") = {2};
Physical Curve("FoundationBottom") = {1}; Physical Curve("FoundationTop") = {3};
Physical Curve("BlockBottom") = {5}; Physical Curve("BlockTop") = {7};

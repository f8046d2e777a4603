// Shallow circular arch (plane strain) for tests/verification/test_stabilization.cpp: mid-surface
// radius R, thickness t, half-angle th (degrees), its ends at y = 0; structured quads, n along
// the arch, m through the thickness. The crown is at (0, R (1 - cos th) + t / 2).
DefineConstant[ R = 10, t = 0.05, th = 10, n = 60, m = 2 ];
a = th * Pi / 180;
yc = -R * Cos(a);
Point(1) = {0, yc, 0};
Point(2) = {-(R - t/2) * Sin(a), yc + (R - t/2) * Cos(a), 0};
Point(3) = {(R - t/2) * Sin(a), yc + (R - t/2) * Cos(a), 0};
Point(4) = {(R + t/2) * Sin(a), yc + (R + t/2) * Cos(a), 0};
Point(5) = {-(R + t/2) * Sin(a), yc + (R + t/2) * Cos(a), 0};
Point(6) = {0, yc + R + t/2, 0};
Circle(1) = {2, 1, 3};
Line(2) = {3, 4};
Circle(3) = {4, 1, 6};
Circle(4) = {6, 1, 5};
Line(5) = {5, 2};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Transfinite Curve{1} = n + 1;
Transfinite Curve{3, 4} = n / 2 + 1;
Transfinite Curve{2, 5} = m + 1;
Transfinite Surface{1} = {2, 3, 4, 5};
Recombine Surface{1};
Physical Surface("Arch") = {1};
Physical Curve("Ends") = {2, 5};
Physical Point("Crown") = {6};

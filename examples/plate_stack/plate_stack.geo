// Three plates stacked (plane strain, the right half: symmetry at x = 0), in mm: the bottom plate
// [0, 20] x [0, 10], the middle one [0, 15] x [10, 18], the top one [0, 10] x [18, 24], each
// meshed on its own (no shared nodes), with element sizes h1 > h2 > h3.
DefineConstant[ h1 = 1.0, h2 = 0.7, h3 = 0.5 ];
Macro Plate
  p1 = newp; Point(p1) = {0, y0, 0, h};
  p2 = newp; Point(p2) = {w, y0, 0, h};
  p3 = newp; Point(p3) = {w, y1, 0, h};
  p4 = newp; Point(p4) = {0, y1, 0, h};
  l1 = newl; Line(l1) = {p1, p2};
  l2 = newl; Line(l2) = {p2, p3};
  l3 = newl; Line(l3) = {p3, p4};
  l4 = newl; Line(l4) = {p4, p1};
  cl = newll; Curve Loop(cl) = {l1, l2, l3, l4};
  s = news; Plane Surface(s) = {cl};
  Recombine Surface{s};
Return
w = 20; y0 = 0; y1 = 10; h = h1; Call Plate;
Physical Surface("Bottom") = {s};
Physical Curve("BottomBase") = {l1};
Physical Curve("BottomSym") = {l4};
Physical Curve("BottomSurface") = {l2, l3};
w = 15; y0 = 10; y1 = 18; h = h2; Call Plate;
Physical Surface("Middle") = {s};
Physical Curve("MiddleSym") = {l4};
Physical Curve("MiddleSurface") = {l1, l2, l3};
w = 10; y0 = 18; y1 = 24; h = h3; Call Plate;
Physical Surface("Top") = {s};
Physical Curve("TopSym") = {l4};
Physical Curve("TopSurface") = {l1, l2};
Physical Curve("TopFace") = {l3};

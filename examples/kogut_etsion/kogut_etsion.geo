// A hemisphere of radius R on a rigid flat, axisymmetric (x = r, y = axial): the quarter disc
// centred at (0, R), touching the flat at the origin, cut at y = R. Quadratic quadrilaterals of
// size max(hc, grow d) at a distance d from the contact point (at most hf), so that the
// contact edge is resolved to the same fraction of the contact radius at every load.
DefineConstant[ R = 10, hc = 0.002, grow = 0.06, hf = 1.0, order = 2 ];
Point(1) = {0, 0, 0, hc};
Point(2) = {0, R, 0, hf};
Point(3) = {R, R, 0, hf};
Circle(1) = {1, 2, 3};
Line(2) = {3, 2};
Line(3) = {2, 1};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = MathEval;
Field[2].F = Sprintf("Min(%g, Max(%g, %g * F1))", hf, hc, grow);
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("Sphere") = {1};
Physical Curve("Surface") = {1};
Physical Curve("Top") = {2};
Physical Curve("Axis") = {3};

// The block of examples/rolling_ball and the ball as a meshed rigid body: the cap of the sphere
// of radius R centred at (0, 0, R) below the height `cap` (the part that touches the block),
// its surface of size hb within 2.2 mm of its lowest point, and the centre as a node of its own
// (the reference node; it lies outside the cap).
SetFactory("OpenCASCADE");
DefineConstant[ W = 4, H = 4, hc = 0.2, hf = 1.2, R = 10, cap = 0.6, hb = 0.2, hd = 1.0 ];
Box(1) = {-W, -W, -H, 2 * W, 2 * W, H};
Sphere(2) = {0, 0, R, R};
Box(3) = {-R, -R, 0, 2 * R, 2 * R, cap};
BooleanIntersection(4) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
Point(100) = {0, 0, R};
eps = 1e-6;
capTop() = Surface In BoundingBox{-R, -R, cap - eps, R, R, cap + eps};
capAll() = Boundary{ Volume{4}; };
capCurved() = capAll();
capCurved() -= {capTop()};
Physical Volume("Block") = {1};
Physical Volume("Ball") = {4};
Physical Surface("Top") = {Surface In BoundingBox{-W - eps, -W - eps, -eps, W + eps, W + eps, eps}};
Physical Surface("Bottom") = {Surface In BoundingBox{-W - eps, -W - eps, -H - eps, W + eps, W + eps, -H + eps}};
Physical Surface("Cap") = {capCurved()};
Physical Point("Centre") = {100};
// The block as in examples/rolling_ball; the cap fine near its lowest point.
Field[1] = Box;
Field[1].VIn = hc;
Field[1].VOut = hf;
Field[1].XMin = -1.0;
Field[1].XMax = 1.9;
Field[1].YMin = -1.0;
Field[1].YMax = 1.5;
Field[1].ZMin = -0.9;
Field[1].ZMax = 0.1;
Field[1].Thickness = 2.0;
Field[2] = Ball;
Field[2].Radius = 2.2;
Field[2].XCenter = 0;
Field[2].YCenter = 0;
Field[2].ZCenter = 0;
Field[2].VIn = hb;
Field[2].VOut = hd;
Field[2].Thickness = 1.0;
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// dynpm sample: a sheet-metal hat-section rail (open top-hat profile with two
// flanges and drafted walls) with crush-initiator holes near the clamped end.
// Units: mm.  Mesh: quad-dominant; the patch of the top face around the round
// hole is free-meshed with triangles (as a pre-processor's free-mesh patch).
//   gmsh -2 rail.geo -format inp -o rail_mesh.inp
SetFactory("OpenCASCADE");

L  = 350;   // rail length (z)
H  = 40;    // hat depth (y)
Wt = 50;    // width of the hat top
Wb = 70;    // width between the wall feet
F  = 20;    // flange width
Z1 = 18;    // the triangle patch on the top face spans Z1 <= z <= Z2
Z2 = 42;
h  = 5.5;   // target element size

// cross-section (x across, y up), swept along z in three segments
zs[] = {0, Z1, Z2, L};
For k In {0:2}
  z = zs[k];
  p1 = newp; Point(p1) = {-Wb/2 - F, 0, z};
  p2 = newp; Point(p2) = {-Wb/2,     0, z};
  p3 = newp; Point(p3) = {-Wt/2,     H, z};
  p4 = newp; Point(p4) = { Wt/2,     H, z};
  p5 = newp; Point(p5) = { Wb/2,     0, z};
  p6 = newp; Point(p6) = { Wb/2 + F, 0, z};
  c1 = newl; Line(c1) = {p1, p2};
  c2 = newl; Line(c2) = {p2, p3};
  c3 = newl; Line(c3) = {p3, p4};
  c4 = newl; Line(c4) = {p4, p5};
  c5 = newl; Line(c5) = {p5, p6};
  Extrude {0, 0, zs[k+1] - z} { Curve{c1, c2, c3, c4, c5}; }
EndFor
plates[] = Surface{:};

// crush initiators: a round hole (d 18) in the top at z = 30 and a hole
// (d 12) through both walls at z = 75
Cylinder(100) = {0, H - 10, (Z1 + Z2)/2,  0, 20, 0,  9};
Cylinder(101) = {-Wb, H/2, 75,  2*Wb, 0, 0,  6};
BooleanDifference{ Surface{plates[]}; Delete; }{ Volume{100, 101}; Delete; }
Coherence;

eps = 1e-3;
tri[] = Surface In BoundingBox{-Wt/2 - eps, H - eps, Z1 - eps, Wt/2 + eps, H + eps, Z2 + eps};
all[] = Surface{:};
quad[] = all[];
quad[] -= tri[];

Physical Surface("SHELL") = all[];
Physical Curve("ROOT") = Curve In BoundingBox{-1e3, -1e3, -eps, 1e3, 1e3, eps};
Physical Curve("TIP")  = Curve In BoundingBox{-1e3, -1e3, L - eps, 1e3, 1e3, L + eps};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;              // frontal-Delaunay (8 crashes in gmsh 4.8.4 here)
Mesh.RecombinationAlgorithm = 1; // blossom
Recombine Surface{quad[]};
Mesh.ElementOrder = 1;
Mesh.SaveGroupsOfNodes = 1;

// The paper's elastic rod (Fig. 4) as a 2-D body: a rectangle of width w and length L whose
// tip faces the rotor from above; the far end is clamped. Structured mesh.
//
// Parameters (SI):
//   L   length (m)
//   w   width (m); with the scene's thickness t, the section is w·t
//   y0  distance from the rotor axis to the tip (m) (the scene may move the rod to its
//       clearance with `clearance`/`clearance_nd` and approach_deg = 90)
//   nx  elements across the width
//   ny  elements along the length
//
// Physical groups:
//   stator          the rod (surface)
//   stator_contact  the tip edge (curve)
//   stator_fixed    the far edge (curve)
SetFactory("OpenCASCADE");
DefineConstant[
  L = {0.04, Min 0.0001, Name "Parameters/L"},
  w = {0.005, Min 1e-05, Name "Parameters/w"},
  y0 = 0.0601,
  nx = {4, Min 1, Name "Parameters/nx"},
  ny = {16, Min 1, Name "Parameters/ny"}
];

Rectangle(1) = {-w/2, y0, 0, w, L};
// OCC rectangle curves: 1 bottom (tip), 2 right, 3 top (clamped), 4 left.
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1};

Physical Surface("stator") = {1};
Physical Curve("stator_contact") = {1};
Physical Curve("stator_fixed") = {3};

// Plain annulus (a ring stator or seal land) around the rotor axis, in the station plane z = 0.
//
// Parameters (SI, set from a scene's `parameters` table or `rubsim mesh --set name=value`):
//   ri  inner radius (m): the station radius plus the radial clearance
//   ro  outer radius (m)
//   h   target element size (m)
//   n   elements around the circumference, both circles (0: from h)
//   ni  elements around the inner (contact) circle alone (0: as n); the benchmark keeps it
//       fixed while h refines the interior
//
// Physical groups (the contract with scenes):
//   stator          the ring (surface; material region)
//   stator_contact  the inner circle (curve): nodes the rotor can touch
//   stator_fixed    the outer circle (curve): clamped
SetFactory("OpenCASCADE");
DefineConstant[
  ri = {0.0601, Min 0.0001, Name "Parameters/ri"},
  ro = {0.08, Min 0.0001, Name "Parameters/ro"},
  h = {0.004, Min 1e-05, Name "Parameters/h"},
  n = {0, Min 0, Name "Parameters/n"},
  ni = {0, Min 0, Name "Parameters/ni"}
];
If (ri >= ro)
  Error("annulus.geo: the inner radius ri = %g must be below the outer radius ro = %g", ri, ro);
  Abort;
EndIf

Disk(1) = {0, 0, 0, ro, ro};
Disk(2) = {0, 0, 0, ri, ri};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
b() = Boundary{ Surface{3}; };
// Outer circle first, inner second (the order BooleanDifference leaves them in).
outer = b(0);
inner = b(1);
If (n > 0)
  Transfinite Curve{outer, inner} = n + 1;
EndIf
If (ni > 0)
  Transfinite Curve{inner} = ni + 1;
EndIf
// A fixed boundary (`n`) much coarser than h: gmsh's default Frontal-Delaunay (4.8) then
// silently leaves the interior nearly unmeshed (n = 128, h = 0.001: 512 nodes against 2462 at
// h = 0.002); its Delaunay honours h there. The switch is taken only where the outer spacing
// exceeds 2 h (times `size_factor`; Frontal-Delaunay held to 2.8 h in every case tried), so
// meshes with a boundary near h are unchanged.
If (n > 0)
  If (2 * Pi * ro / n > 2 * h * Mesh.MeshSizeFactor)
    Mesh.Algorithm = 5;
  EndIf
EndIf
Mesh.MeshSizeMax = h;
Mesh.MeshSizeMin = 0;

Physical Surface("stator") = {3};
Physical Curve("stator_contact") = {inner};
Physical Curve("stator_fixed") = {outer};

// Labyrinth seal ring (3-D): a tube carrying `teeth` annular fins whose tips face the rotor,
// centred on the station plane z = 0 (rotor axis z). Its outer surface and end faces sit in
// the casing.
//
// Parameters (SI):
//   rt     tooth tip radius (m): station radius + clearance
//   rc     inner radius of the carrier tube, at the teeth roots (m)
//   ro     outer radius (m)
//   teeth  number of teeth
//   pitch  axial pitch of the teeth (m)
//   tooth  axial thickness of a tooth (m)
//   margin carrier length beyond the outer teeth, each side (m)
//   h      element size (m)
//   ht     element size on the tooth tips (m)
//   hxt    1: gmsh's HXT tetrahedral mesher (Mesh.Algorithm3D = 10) instead of its default
//          Delaunay — 3.6x faster at 1e6 cells (h = ht = 0.0005: 18 s against 65 s, one
//          thread), another mesh of the same sizes; 0 (default): the Delaunay mesh
//   hi     element size inside the seal (m), away from the tooth tips: every geometry point but
//          the tips' gets hi, the tips keep ht, and sizes in between grade from the boundary.
//          Refines the interior while the contact surfaces keep their nodes (the shipped
//          seal's 2 277 tip nodes at hi = 0.001, 0.0005 or 0.00038 — 0.1, 0.5 and 1.0 million
//          DOFs); needs h >= ht. 0 (default): no interior size, h everywhere but the tips
//
// Physical groups:
//   stator          the seal (volume)
//   stator_contact  the tooth tips (cylindrical surfaces)
//   stator_fixed    the outer cylinder and the end faces (surfaces)
SetFactory("OpenCASCADE");
DefineConstant[
  rt = {0.0602, Min 0.0001, Name "Parameters/rt"},
  rc = {0.064, Min 0.0001, Name "Parameters/rc"},
  ro = {0.068, Min 0.0001, Name "Parameters/ro"},
  teeth = {3, Min 1, Name "Parameters/teeth"},
  pitch = {0.004, Min 0.0001, Name "Parameters/pitch"},
  tooth = {0.001, Min 1e-05, Name "Parameters/tooth"},
  margin = {0.002, Min 0, Name "Parameters/margin"},
  h = {0.003, Min 1e-05, Name "Parameters/h"},
  ht = {0.0015, Min 1e-05, Name "Parameters/ht"},
  hxt = {0, Min 0, Max 1, Name "Parameters/hxt"},
  hi = {0, Min 0, Name "Parameters/hi"}
];
// Refuse at once what the construction cannot build (gmsh would otherwise grind on it).
If (teeth != Round(teeth))
  Error("labyrinth_seal.geo: teeth = %g must be a whole number", teeth);
  Abort;
EndIf
If (!(rt < rc && rc < ro))
  Error("labyrinth_seal.geo: the radii must satisfy rt < rc < ro (rt = %g, rc = %g, ro = %g)", rt, rc, ro);
  Abort;
EndIf
If (teeth > 1 && pitch <= tooth)
  Error("labyrinth_seal.geo: pitch = %g must exceed the tooth thickness tooth = %g", pitch, tooth);
  Abort;
EndIf

L = (teeth - 1) * pitch + tooth + 2 * margin;
z0 = -L / 2;
Cylinder(1) = {0, 0, z0, 0, 0, L, ro};
Cylinder(2) = {0, 0, z0, 0, 0, L, rc};
tube() = BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; };
fins() = {};
For i In {0:teeth-1}
  zi = -(teeth - 1) * pitch / 2 + i * pitch;
  a = newv; Cylinder(a) = {0, 0, zi - tooth / 2, 0, 0, tooth, (rc + ro) / 2};
  b = newv; Cylinder(b) = {0, 0, zi - tooth / 2, 0, 0, tooth, rt};
  f() = BooleanDifference{ Volume{a}; Delete; }{ Volume{b}; Delete; };
  fins() += f();
EndFor
seal() = BooleanUnion{ Volume{tube()}; Delete; }{ Volume{fins()}; Delete; };

e = 1e-6;
tips() = {};
For i In {0:teeth-1}
  zi = -(teeth - 1) * pitch / 2 + i * pitch;
  tips() += Surface In BoundingBox{-rt - e, -rt - e, zi - tooth / 2 - e, rt + e, rt + e, zi + tooth / 2 + e};
EndFor
// Outer cylinder and end faces: every surface reaching beyond the carrier's inner radius.
inner() = Surface In BoundingBox{-rc - e, -rc - e, z0 - e, rc + e, rc + e, z0 + L + e};
all() = Surface{:};
outer() = {};
For i In {0:#all()-1}
  isin = 0;
  For j In {0:#inner()-1}
    If (inner(j) == all(i)) isin = 1; EndIf
  EndFor
  If (isin == 0) outer() += all(i); EndIf
EndFor

If (hxt == 1)
  Mesh.Algorithm3D = 10;
EndIf
Mesh.MeshSizeMax = h;
If (hi > 0)
  MeshSize{ PointsOf{ Volume{seal()}; } } = hi;
EndIf
MeshSize{ PointsOf{ Surface{tips()}; } } = ht;

Physical Volume("stator") = {seal()};
Physical Surface("stator_contact") = {tips()};
Physical Surface("stator_fixed") = {outer()};

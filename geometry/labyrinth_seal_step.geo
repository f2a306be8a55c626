// The labyrinth seal imported from CAD: labyrinth_seal.step (exported from labyrinth_seal.geo
// with its default parameters by `gmsh labyrinth_seal.geo -0 -o labyrinth_seal.step`), meshed
// through OpenCASCADE like any STEP part. The physical groups are picked geometrically, by
// bounding boxes built from the part's known dimensions (those of labyrinth_seal.geo's
// defaults) — the usual way of naming the faces of a CAD part for a scene.
//
// Parameters (SI): only mesh sizes; the geometry is the file's.
//   h   element size (m)
//   ht  element size on the tooth tips (m)
//
// Physical groups: as labyrinth_seal.geo (stator, stator_contact, stator_fixed).
SetFactory("OpenCASCADE");
DefineConstant[
  h = {0.003, Min 1e-05, Name "Parameters/h"},
  ht = {0.0015, Min 1e-05, Name "Parameters/ht"}
];
// Dimensions of the part in the STEP file (m).
rt = 0.0602; rc = 0.064; teeth = 3; pitch = 0.004; tooth = 0.001; margin = 0.002;

v() = ShapeFromFile("labyrinth_seal.step");
L = (teeth - 1) * pitch + tooth + 2 * margin;
z0 = -L / 2;
e = 1e-6;
tips() = {};
For i In {0:teeth-1}
  zi = -(teeth - 1) * pitch / 2 + i * pitch;
  tips() += Surface In BoundingBox{-rt - e, -rt - e, zi - tooth / 2 - e, rt + e, rt + e, zi + tooth / 2 + e};
EndFor
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

Mesh.MeshSizeMax = h;
MeshSize{ PointsOf{ Surface{tips()}; } } = ht;

Physical Volume("stator") = {v()};
Physical Surface("stator_contact") = {tips()};
Physical Surface("stator_fixed") = {outer()};

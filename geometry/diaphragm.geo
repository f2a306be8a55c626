// Turbine diaphragm in the station plane: a ring split at its horizontal joint into an upper
// and a lower half, the halves held together by a joint layer (bolted flange, modelled as a
// thin region of its own material), resting on two support lugs at the joint and guided by a
// key at the bottom. Plane stress with the scene's axial thickness.
//
// Parameters (SI):
//   ri  inner (seal) radius facing the rotor (m): station radius + clearance
//   ro  outer radius (m)
//   tj  thickness of the joint layer across the horizontal joint (m)
//   wl  radial length of the support lugs beyond ro (m)
//   hl  height of the lugs (m)
//   wk  width of the bottom key (m)
//   hk  depth of the key below ro (m)
//   h   element size (m)
//   hc  element size on the inner (contact) circle (m)
//
// Physical groups:
//   stator          upper and lower halves (surfaces; material region)
//   joint           the joint layer (surfaces; a region the scene gives the joint's stiffness)
//   stator_contact  the inner circle (curves)
//   stator_fixed    the end faces of the lugs (curves): resting on the casing
//   key             the bottom face of the key (curve): guided horizontally (fixed_x)
SetFactory("OpenCASCADE");
DefineConstant[
  ri = {0.0602, Min 0.0001, Name "Parameters/ri"},
  ro = {0.11, Min 0.0001, Name "Parameters/ro"},
  tj = {0.002, Min 1e-05, Name "Parameters/tj"},
  wl = {0.012, Min 1e-05, Name "Parameters/wl"},
  hl = {0.016, Min 1e-05, Name "Parameters/hl"},
  wk = {0.01, Min 1e-05, Name "Parameters/wk"},
  hk = {0.006, Min 1e-05, Name "Parameters/hk"},
  h = {0.004, Min 1e-05, Name "Parameters/h"},
  hc = {0.0015, Min 1e-05, Name "Parameters/hc"}
];
If (ri >= ro)
  Error("diaphragm.geo: the inner radius ri = %g must be below the outer radius ro = %g", ri, ro);
  Abort;
EndIf

Disk(1) = {0, 0, 0, ro, ro};
Disk(2) = {0, 0, 0, ri, ri};
Rectangle(3) = {ro - 0.002, -hl / 2, 0, wl + 0.002, hl};
Rectangle(4) = {-ro - wl, -hl / 2, 0, wl + 0.002, hl};
Rectangle(5) = {-wk / 2, -ro - hk, 0, wk, hk + 0.002};
body() = BooleanUnion{ Surface{1}; Delete; }{ Surface{3, 4, 5}; Delete; };
ring() = BooleanDifference{ Surface{body()}; Delete; }{ Surface{2}; Delete; };
// The joint layer: the ring's intersection with a strip across the horizontal plane, fused
// back so that it splits the ring into its halves.
Rectangle(10) = {-ro - wl - 0.01, -tj / 2, 0, 2 * (ro + wl + 0.01), tj};
copy() = Translate{0, 0, 0}{ Duplicata{ Surface{ring()}; } };
strip() = BooleanIntersection{ Surface{copy()}; Delete; }{ Surface{10}; Delete; };
parts() = BooleanFragments{ Surface{ring()}; Delete; }{ Surface{strip()}; Delete; };
e = 1e-6;
upper() = Surface In BoundingBox{-1, tj / 2 - e, -e, 1, 1, e};
lower() = Surface In BoundingBox{-1, -1, -e, 1, -tj / 2 + e, e};
joint() = Surface In BoundingBox{-1, -tj / 2 - e, -e, 1, tj / 2 + e, e};

contact() = Curve In BoundingBox{-ri - e, -ri - e, -e, ri + e, ri + e, e};
lugs() = Curve In BoundingBox{ro + wl - e, -hl / 2 - e, -e, ro + wl + e, hl / 2 + e, e};
lugs() += Curve In BoundingBox{-ro - wl - e, -hl / 2 - e, -e, -ro - wl + e, hl / 2 + e, e};
key() = Curve In BoundingBox{-wk / 2 - e, -ro - hk - e, -e, wk / 2 + e, -ro - hk + e, e};

Mesh.MeshSizeMax = h;
MeshSize{ PointsOf{ Curve{contact()}; } } = hc;

Physical Surface("stator") = {upper(), lower()};
Physical Surface("joint") = {joint()};
Physical Curve("stator_contact") = {contact()};
Physical Curve("stator_fixed") = {lugs()};
Physical Curve("key") = {key()};

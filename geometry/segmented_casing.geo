// Segmented casing in the station plane: n arc segments (annular sectors) around the rotor,
// separated by gaps, each carried by two radial support beams from its outer surface to the
// frame. The beams are line elements the scene models as frames (or bars); alternatively the
// scene puts springs on the `mount` points and leaves the beams out.
//
// Parameters (SI):
//   n     number of segments
//   ri    inner radius facing the rotor (m): station radius + clearance
//   ro    outer radius of the segments (m)
//   gap   angular gap between neighbouring segments (degrees)
//   lb    length of the support beams (m)
//   phi0  angle of the first segment's centre (degrees from +x)
//   h     element size (m)
//   hc    element size on the inner arcs (m)
//
// Physical groups:
//   stator          the segments (surfaces)
//   stator_contact  their inner arcs (curves)
//   support         the beams (curves)
//   stator_fixed    the beams' outer ends (points): clamped to the frame
//   mount           the beams' roots on the segments (points)
SetFactory("OpenCASCADE");
DefineConstant[
  n = {6, Min 1, Name "Parameters/n"},
  ri = {0.0602, Min 0.0001, Name "Parameters/ri"},
  ro = {0.075, Min 0.0001, Name "Parameters/ro"},
  gap = {4, Min 0, Name "Parameters/gap"},
  lb = {0.03, Min 1e-05, Name "Parameters/lb"},
  phi0 = 90,
  h = {0.003, Min 1e-05, Name "Parameters/h"},
  hc = {0.0015, Min 1e-05, Name "Parameters/hc"}
];
If (ri >= ro || n != Round(n))
  Error("segmented_casing.geo: needs ri < ro (ri = %g, ro = %g) and a whole number of segments (n = %g)", ri, ro, n);
  Abort;
EndIf

Disk(1) = {0, 0, 0, ro, ro};
Disk(2) = {0, 0, 0, ri, ri};
ring() = BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; Delete; };
// Cut the gaps with thin wedges.
R = 2 * ro;
g = gap * Pi / 180;
wedges() = {};
For i In {0:n-1}
  a = (phi0 + (i + 0.5) * 360 / n) * Pi / 180;
  p1 = newp; Point(p1) = {0, 0, 0};
  p2 = newp; Point(p2) = {R * Cos(a - g / 2), R * Sin(a - g / 2), 0};
  p3 = newp; Point(p3) = {R * Cos(a + g / 2), R * Sin(a + g / 2), 0};
  l1 = newl; Line(l1) = {p1, p2};
  l2 = newl; Line(l2) = {p2, p3};
  l3 = newl; Line(l3) = {p3, p1};
  cl = newll; Curve Loop(cl) = {l1, l2, l3};
  w = news; Plane Surface(w) = {cl};
  wedges() += w;
EndFor
segs() = BooleanDifference{ Surface{ring()}; Delete; }{ Surface{wedges()}; Delete; };
// Two radial beams per segment, at ±span/4 from its centre.
beams() = {};
For i In {0:n-1}
  For s In {-1:1:2}
    a = (phi0 + i * 360 / n + s * (360 / n - gap) / 4) * Pi / 180;
    q1 = newp; Point(q1) = {ro * Cos(a), ro * Sin(a), 0};
    q2 = newp; Point(q2) = {(ro + lb) * Cos(a), (ro + lb) * Sin(a), 0};
    b = newl; Line(b) = {q1, q2};
    beams() += b;
  EndFor
EndFor
all() = BooleanFragments{ Surface{segs()}; Delete; }{ Curve{beams()}; Delete; };
e = 1e-6;
body() = Surface{:};
contact() = Curve In BoundingBox{-ri - e, -ri - e, -e, ri + e, ri + e, e};
// Beams: the curves that lie outside the segments' radius.
sup() = {};
ends() = {};
roots() = {};
For i In {0:n-1}
  For s In {-1:1:2}
    a = (phi0 + i * 360 / n + s * (360 / n - gap) / 4) * Pi / 180;
    xa = ro * Cos(a); ya = ro * Sin(a);
    xb = (ro + lb) * Cos(a); yb = (ro + lb) * Sin(a);
    sup() += Curve In BoundingBox{Min(xa, xb) - e, Min(ya, yb) - e, -e, Max(xa, xb) + e, Max(ya, yb) + e, e};
    ends() += Point In BoundingBox{xb - e, yb - e, -e, xb + e, yb + e, e};
    roots() += Point In BoundingBox{xa - e, ya - e, -e, xa + e, ya + e, e};
  EndFor
EndFor

Mesh.MeshSizeMax = h;
MeshSize{ PointsOf{ Curve{contact()}; } } = hc;

Physical Surface("stator") = {body()};
Physical Curve("stator_contact") = {contact()};
Physical Curve("support") = {sup()};
Physical Point("stator_fixed") = {ends()};
Physical Point("mount") = {roots()};

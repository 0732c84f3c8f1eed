// Double friction pendulum bearing in its plane of motion, for the 2-D plane-strain FE model.
//
// x horizontal, y vertical, metres. The bottom plate's dish apex is the origin; the slider
// (rigid in the FE model, not meshed) sits between the two dishes, so the top plate's dish
// apex is at y = h_slider. The top plate is the bottom plate mirrored about y = h_slider/2;
// the superstructure block sits on the top plate's back face (shared, conforming line).
//
// Parameters are injected by fem/geometry.py from a rigid.DFPBearing with
// gmsh.parser.setNumber(); the defaults below are those of DFPBearing() and only apply when
// the file is opened by hand (gmsh meshes/dfp.geo).
//
//   R          radius of both concave dishes (DFPBearing.radius)
//   r_in       horizontal distance of the rims' inner faces from the axis (rim_radius)
//   r_out      outer radius of the plates (plate_radius = r_in + rim_thickness)
//   h_rim      rim height above the dish at the rim's inner face (rim_height)
//   t_plate    plate thickness under the dish apex (plate_thickness)
//   h_slider   slider height on its axis (slider_height)
//   h_block    height of the superstructure block (FE model only)
//   lc_rim     element size at the rims (inner face, top, root)
//   lc_contact element size along the dishes
//   lc_coarse  element size far from both
//
// The mesh is all quadrilateral: the rims are structured (transfinite), the rest is
// triangulated and recombined (Blossom), and then every element is split
// once (Mesh.SubdivisionAlgorithm = 1), which halves the sizes; fem/geometry.py doubles the
// requested sizes before injecting them, so the lc_* values here are pre-subdivision sizes.

DefineConstant[
  R = 2.5, r_in = 0.5099, r_out = 0.5499, h_rim = 0.035, t_plate = 0.06, h_slider = 0.2,
  h_block = 0.1, lc_rim = 0.01, lc_contact = 0.02, lc_coarse = 0.06
];

z_r = R - Sqrt(R^2 - r_in^2);   // dish height at the rims' inner faces (rim root level)
z_t = z_r + h_rim;              // top of the rims
h = h_slider;

// ---- bottom plate ------------------------------------------------------------------
Point(1) = {-r_out, -t_plate, 0, lc_coarse};
Point(2) = { r_out, -t_plate, 0, lc_coarse};
Point(3) = { r_out, z_r, 0, lc_coarse};
Point(4) = { r_in, z_r, 0, lc_coarse};
Point(5) = {-r_in, z_r, 0, lc_coarse};
Point(6) = {-r_out, z_r, 0, lc_coarse};
Point(7) = { r_in, z_t, 0, lc_coarse};
Point(8) = { r_out, z_t, 0, lc_coarse};
Point(9) = {-r_in, z_t, 0, lc_coarse};
Point(10) = {-r_out, z_t, 0, lc_coarse};
Point(11) = {0, R, 0, lc_coarse};     // centre of the bottom dish

Line(1) = {1, 2};        // back face: support
Line(2) = {2, 3};
Line(3) = {4, 3};        // right rim root (interior)
Circle(4) = {4, 11, 5};  // dish
Line(5) = {6, 5};        // left rim root (interior)
Line(6) = {6, 1};
Line(7) = {3, 8};
Line(8) = {8, 7};        // right rim top
Line(9) = {7, 4};        // right rim inner face
Line(10) = {5, 9};       // left rim inner face
Line(11) = {9, 10};      // left rim top
Line(12) = {10, 6};

Curve Loop(1) = {1, 2, -3, 4, -5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {3, 7, 8, 9};
Plane Surface(2) = {2};
Curve Loop(3) = {5, 10, 11, 12};
Plane Surface(3) = {3};

// ---- top plate: mirror image about y = h/2, loops reversed to stay counter-clockwise --
Point(21) = {-r_out, h + t_plate, 0, lc_coarse};
Point(22) = { r_out, h + t_plate, 0, lc_coarse};
Point(23) = { r_out, h - z_r, 0, lc_coarse};
Point(24) = { r_in, h - z_r, 0, lc_coarse};
Point(25) = {-r_in, h - z_r, 0, lc_coarse};
Point(26) = {-r_out, h - z_r, 0, lc_coarse};
Point(27) = { r_in, h - z_t, 0, lc_coarse};
Point(28) = { r_out, h - z_t, 0, lc_coarse};
Point(29) = {-r_in, h - z_t, 0, lc_coarse};
Point(30) = {-r_out, h - z_t, 0, lc_coarse};
Point(31) = {0, h - R, 0, lc_coarse};  // centre of the top dish

Line(21) = {21, 22};       // back face, shared with the block
Line(22) = {22, 23};
Line(23) = {24, 23};       // right rim root (interior)
Circle(24) = {24, 31, 25}; // dish
Line(25) = {26, 25};       // left rim root (interior)
Line(26) = {26, 21};
Line(27) = {23, 28};
Line(28) = {28, 27};       // right rim top (faces down)
Line(29) = {27, 24};       // right rim inner face
Line(30) = {25, 29};       // left rim inner face
Line(31) = {29, 30};       // left rim top (faces down)
Line(32) = {30, 26};

Curve Loop(21) = {-26, 25, -24, 23, -22, -21};
Plane Surface(21) = {21};
Curve Loop(22) = {-29, -28, -27, -23};
Plane Surface(22) = {22};
Curve Loop(23) = {-32, -31, -30, -25};
Plane Surface(23) = {23};

// ---- superstructure block ------------------------------------------------------------
Point(41) = { r_out, h + t_plate + h_block, 0, lc_coarse};
Point(42) = {-r_out, h + t_plate + h_block, 0, lc_coarse};
Line(41) = {22, 41};
Line(42) = {41, 42};       // block top
Line(43) = {42, 21};
Curve Loop(41) = {21, 41, 42, 43};
Plane Surface(41) = {41};

// ---- physical groups ---------------------------------------------------------------------
Physical Surface("bottom_plate", 1) = {1};
Physical Surface("bottom_rim", 2) = {2, 3};
Physical Surface("top_plate", 3) = {21};
Physical Surface("top_rim", 4) = {22, 23};
Physical Surface("block", 5) = {41};

Physical Curve("support", 11) = {1};
Physical Curve("bottom_dish", 12) = {4};
Physical Curve("bottom_rim_inner", 13) = {9, 10};
Physical Curve("bottom_rim_top", 14) = {8, 11};
Physical Curve("bottom_rim_root", 15) = {3, 5};
Physical Curve("top_dish", 22) = {24};
Physical Curve("top_rim_inner", 23) = {29, 30};
Physical Curve("top_rim_top", 24) = {28, 31};
Physical Curve("top_rim_root", 25) = {23, 25};
Physical Curve("block_top", 31) = {42};

// ---- rims: structured quadrilaterals (regular elements for the plastic hinge at the root) ---
n_t = Ceil((r_out - r_in) / lc_rim) + 1;
n_h = Ceil(h_rim / lc_rim) + 1;
Transfinite Curve{3, 8, 5, 11, 23, 28, 25, 31} = n_t;
Transfinite Curve{7, 9, 10, 12, 27, 29, 30, 32} = n_h;
Transfinite Surface{2, 3, 22, 23};

// ---- mesh size: fine at the rims (roots, inner faces, tops) and along the dishes -----------
Field[1] = Distance;
Field[1].CurvesList = {3, 5, 8, 9, 10, 11, 23, 25, 28, 29, 30, 31};
Field[1].Sampling = 50;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = lc_rim;
Field[2].SizeMax = lc_coarse;
Field[2].DistMin = 0.5 * (r_out - r_in);
Field[2].DistMax = 3 * (r_out - r_in);
Field[3] = Distance;
Field[3].CurvesList = {4, 24};
Field[3].Sampling = 400;
Field[4] = Threshold;
Field[4].InField = 3;
Field[4].SizeMin = lc_contact;
Field[4].SizeMax = lc_coarse;
Field[4].DistMin = 0.25 * t_plate;
Field[4].DistMax = t_plate;
Field[5] = Min;
Field[5].FieldsList = {2, 4};
Background Field = 5;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 5;               // Delaunay; with smoothing it gave the best quad angles
Mesh.Smoothing = 10;
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.SubdivisionAlgorithm = 1;    // all quadrilaterals
Mesh.ElementOrder = 1;
Mesh.MshFileVersion = 4.1;

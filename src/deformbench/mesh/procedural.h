#pragma once
//! Procedural test shapes at any resolution, and the analytic deformations they are meant to undergo
//! (the "ideal" a linear method is compared against).
//!
//! Conventions, shared by all generators and ideal deformations:
//! - the long axis is +z; cylinder and bar occupy z in [0, height]; the plane lies in z = 0 plus bumps;
//! - faces are counter-clockwise seen from outside (outward normals);
//! - resolutions below the minimum and non-positive sizes are InputError.
#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

//! Open tube of radius `radius` around the z axis from z = 0 to z = height (no caps).
//! `rings` (>= 2) vertex rings evenly spaced along z, `segments` (>= 3) vertices per ring; ring i, vertex j sits at
//! angle 2*pi*j/segments and has index i*segments + j. #V = rings*segments, #F = 2*(rings-1)*segments.
//! Name "cylinder_<rings>x<segments>".
Mesh make_cylinder(int rings, int segments, double radius, double height);

//! Closed box surface [-sx/2, sx/2] x [-sy/2, sy/2] x [0, sz] with nx, ny, nz (>= 1) cells along x, y, z on
//! every side; vertices are shared between sides, so the surface is a closed 2-manifold.
//! #V = (nx+1)(ny+1)(nz+1) - (nx-1)(ny-1)(nz-1), #F = 4(nx*ny + ny*nz + nz*nx). Name "bar_<nx>x<ny>x<nz>".
Mesh make_bar(int nx, int ny, int nz, double sx, double sy, double sz);

//! Square height field over [-size/2, size/2]^2 with nx, ny (>= 1) cells along x and y, vertex (i, j) at index
//! j*(nx+1) + i and height z = bump_height * sin(2*pi*bumps*u) * sin(2*pi*bumps*v), u, v in [0, 1] the
//! normalized grid coordinates: `bumps` bumps per side, zero on the border. Name "plane_<nx>x<ny>".
Mesh make_bumpy_plane(int nx, int ny, double size, double bump_height, int bumps);

//! Bends the slab z in [z0, z1] (length L = z1 - z0) about an axis parallel to x into a circular arc of total angle
//! `angle_rad` (radius R = L / angle), curving towards +y for a positive angle:
//!   z < z0:            unchanged;
//!   z0 <= z <= z1:     theta = angle * (z - z0) / L,  p' = (x, R - (R - y) cos theta, z0 + (R - y) sin theta);
//!   z > z1:            rigid motion continuing the end frame (rotation by -angle about x, then translation).
//! The neutral plane y = 0 keeps its length (the z axis maps to an arc of length L); fibres at offset y are
//! stretched by (R - y) / R as in a bent beam. angle = 0 is the identity. \throw InputError when z1 <= z0.
Points ideal_bend(const Points& V, double angle_rad, double z0, double z1);

//! Twists about the z axis: each point is rotated about z by angle_rad * clamp((z - z0) / (z1 - z0), 0, 1)
//! (counter-clockwise seen from +z for a positive angle). Distances to the z axis and z are preserved.
//! \throw InputError when z1 <= z0.
Points ideal_twist(const Points& V, double angle_rad, double z0, double z1);

//! The rigid motion ideal_bend applies beyond z1, as a handle transform: handle vertices above z1 moved by it land
//! where ideal_bend puts them (the frames experiment and the LRI tests bend tubes with it). angle 0 is the
//! identity. \throw InputError when z1 <= z0.
Mat4 bend_transform(double angle_rad, double z0, double z1);

//! The rigid motion ideal_twist applies beyond z1: a rotation by angle_rad about the z axis.
Mat4 twist_transform(double angle_rad);

}  // namespace db

#pragma once
//! Geometric vertex selections for building edits. All return sorted, duplicate-free vertex ids.
#include <string>
#include <vector>

#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

//! Vertices with |p - center| <= radius. \throw InputError for a negative radius.
std::vector<int> select_sphere(const Mesh& mesh, const Vec3& center, double radius);

//! Vertices inside the axis-aligned box [lo, hi] (bounds included).
//! \throw InputError for an inverted box (lo above hi in some axis), naming the axis.
std::vector<int> select_box(const Mesh& mesh, const Vec3& lo, const Vec3& hi);

//! Vertices at most k edges away from seed (k = 0: the seed alone).
//! \throw InputError for a seed out of range or k < 0.
std::vector<int> select_k_ring(const Adjacency& adjacency, int seed, int k);

//! The `count` vertices closest to point (ties broken by the lower id, so the result is deterministic).
//! \throw InputError when count < 1 or count > #V.
std::vector<int> select_nearest(const Mesh& mesh, const Vec3& point, int count);

//! Parses and applies a selection spec:
//!   all | sphere:cx,cy,cz,r | box:x0,y0,z0,x1,y1,z1 | kring:v,k | nearest:x,y,z,count | indices:FILE
//! (indices: read_index_list, relative FILE resolved against base_dir; ids are range-checked).
//! \throw InputError naming the spec.
std::vector<int> select_by_spec(const Mesh& mesh, const std::string& spec, const std::string& base_dir = "");

}  // namespace db

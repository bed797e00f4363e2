#pragma once
//! STL (stereolithography): a list of triangles, each with its own three corner positions and a facet normal.
//!
//! ASCII: "solid NAME", then per triangle "facet normal nx ny nz", "outer loop", three "vertex x y z" lines,
//! "endloop", "endfacet", and "endsolid [NAME]"; one statement a line, keywords in any case, several solids in one
//! file are read one after the other. Binary: an 80-byte header, a little-endian uint32 triangle count n, then n
//! records of 50 bytes (normal and three corners as 32-bit floats, a 2-byte attribute), 84 + 50 n bytes in all.
//!
//! Which of the two a file is: binary when its size is exactly 84 + 50 n for the n in bytes 80..83, whatever its
//! header says (many binary writers begin the header with "solid"); otherwise ASCII when it begins with "solid";
//! otherwise an error that gives the size the header's count implies. This is the test common readers use.
//!
//! Vertices: STL has none, only corners. Corners whose three coordinates are bitwise equal (as doubles: a binary
//! float widened exactly, an ASCII number parsed exactly) become one vertex, numbered in order of first appearance;
//! faces keep the file's order and corner order. There is no welding with a tolerance: any epsilon would depend on
//! the model's scale, would merge distinct vertices of a fine mesh (and is not transitive: a chain of close points
//! merges into one), and would move positions, so a write and read would no longer give the mesh back. Bitwise
//! also means 0 and -0 are different points; exporters that write both at one place leave a crack there.
//! Facet normals and the binary attribute bytes are read past but not used (anyone who needs normals computes them
//! from the corners).
//!
//! Refused, with the file and the line (ASCII) or the triangle and its byte offset (binary) named: a non-finite
//! coordinate, a degenerate facet (two of its corners the same point, which welding would turn into a repeated
//! index), a file without triangles, a binary file whose size disagrees with its count (checked before anything
//! is allocated), an ASCII file that ends early or breaks the grammar, more than kMaxElements triangles or vertices.
#include <ostream>
#include <string>

#include "mesh/mesh.h"
#include "mesh/mesh_io.h"

namespace db::io {

//! Reads the STL file at `path`, ASCII or binary (decided as above). \throw InputError as above.
Mesh read_stl(const std::string& path);

//! Checks that `mesh` can be written as STL with `encoding` and read back: at least one face, face indices in range
//! and coordinates finite (check_arrays), no face with two corners at the same point as written (binary: after
//! rounding to 32-bit floats), and for binary every coordinate within float range.
//! \throw InputError "cannot write PATH: ..." naming the face or vertex, before any file is opened.
void check_stl_writable(const std::string& path, const Mesh& mesh, StlEncoding encoding);

//! Writes every face as a facet, in order, with its unit normal ((b - a) x (c - a), 0 0 0 for a zero area).
//! ASCII: "solid NAME" (mesh.name), each coordinate as the shortest text that reads back to the same double.
//! Binary: a header that does not begin with "solid", coordinates rounded to the nearest float, attribute 0.
//! Vertices no face uses are not written, and vertices at the same position come back as one (see above).
//! \pre check_stl_writable(path, mesh, encoding) passed.
void write_stl(std::ostream& os, const Mesh& mesh, StlEncoding encoding);

}  // namespace db::io

#pragma once
//! Zero-copy CHOLMOD views of this project's arrays, shared by the CHOLMOD-based code (backends, vertex ordering).
#include <cstddef>
#include <string>

#include <cholmod.h>

namespace db {

//! Symmetric CHOLMOD matrix (stype = +1: only the upper triangle is read) over a sorted, packed CSC array with
//! int indices; `values` null makes it a pattern.
inline cholmod_sparse cholmod_upper_view(std::size_t n, const int* colptr, const int* rows, const double* values) {
  cholmod_sparse A{};
  A.nrow = A.ncol = n;
  A.nzmax = std::size_t(colptr[n]);
  A.p = const_cast<int*>(colptr);
  A.i = const_cast<int*>(rows);
  A.x = const_cast<double*>(values);
  A.stype = 1;
  A.itype = CHOLMOD_INT;
  A.xtype = values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

//! Dense CHOLMOD matrix over a column-major array of nrow x ncol doubles, leading dimension nrow (an Eigen
//! DenseMat's data()).
inline cholmod_dense cholmod_dense_view(std::size_t nrow, std::size_t ncol, const double* values) {
  cholmod_dense D{};
  D.nrow = nrow;
  D.ncol = ncol;
  D.nzmax = nrow * ncol;
  D.d = nrow;
  D.x = const_cast<double*>(values);
  D.xtype = CHOLMOD_REAL;
  D.dtype = CHOLMOD_DOUBLE;
  return D;
}

//! CHOLMOD's code for an ordering name: "amd", "metis", "nesdis"; anything else is natural.
inline int cholmod_ordering_code(const std::string& name) {
  return name == "amd" ? CHOLMOD_AMD : name == "metis" ? CHOLMOD_METIS : name == "nesdis" ? CHOLMOD_NESDIS : CHOLMOD_NATURAL;
}

}  // namespace db

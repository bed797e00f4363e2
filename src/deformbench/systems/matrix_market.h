#pragma once
//! Matrix Market files (NIST's coordinate and array formats) of the systems: out for other solver developers
//! (`deformbench export-system`), in for the solver study (`exp_solvers --matrix`).
//!
//! Written here rather than with Eigen's unsupported/Eigen/SparseExtra MarketIO (3.4): its saveMarket writes full
//! precision (digits10 + 2), but opens its own std::ofstream and returns true after a failed write (no staged,
//! checked output), writes whatever is stored under a "symmetric" header (the format wants one triangle, the
//! lower), and has no multi-column array writer (saveMarketVector: one column); its loadMarket reserves the
//! header's entry count unchecked, skips out-of-range entries with a note on stderr, accepts a wrong entry count
//! and ignores the symmetric header. Values are written with %.17g, which round-trips every double exactly.
#include <ostream>
#include <string>

#include "solvers/base/types.h"

namespace db {

//! A symmetric matrix given by its upper triangle (`upper`, as the builds keep K), written as the format's
//! "coordinate real symmetric": the lower triangle, 1-based, column by column.
void write_market_symmetric(std::ostream& out, const SpMat& upper, const std::string& comment = "");
//! Any sparse matrix (the least-squares A) as "coordinate real general".
void write_market_general(std::ostream& out, const SpMat& A, const std::string& comment = "");
//! A dense matrix (right-hand sides, one column each) as "array real general", column by column.
void write_market_array(std::ostream& out, const DenseMat& B, const std::string& comment = "");

//! A symmetric positive-definite candidate read from a coordinate file: its upper triangle. "symmetric" files
//! must hold the lower triangle only; "general" ones must be exactly symmetric. Every diagonal entry must be
//! present and positive (a necessary condition of positive definiteness; the factorization checks the rest).
//! The header's counts are checked against each other and the file's size before anything is allocated.
//! \throw InputError naming the file, the line and the cause.
SpMat read_market_spd(const std::string& path);
//! An "array real general" file (right-hand sides). \throw InputError as read_market_spd, also when its rows are
//! not `rows` (-1: any).
DenseMat read_market_array(const std::string& path, long long rows = -1);

}  // namespace db

#pragma once
//! What MUMPS reports about an analysis and a factorization (both MUMPS backends); no MPI type.
#include <vector>

namespace db::mumps {

//! MUMPS's own figures after analysis (estimates) and factorization (effective), global over the processes.
//! Sizes MUMPS gives in MB are millions of bytes.
struct Report {
  int processes = 1;
  int ordering_code = -1;           //!< INFOG(7)
  double flops_estimated = 0;       //!< RINFOG(1): elimination flops, from the analysis
  double flops = 0;                 //!< RINFOG(3): elimination flops of the factorization
  double nnz_factor_estimated = 0;  //!< INFOG(20)
  double factor_entries_estimated = 0;  //!< INFOG(3): real entries the factor will take, from the analysis
  double nnz_factor = 0;            //!< INFOG(29)
  double factor_entries = 0;        //!< INFOG(9): real entries allocated for the factor
  double factor_integers = 0;       //!< INFOG(10)
  int max_front = 0;                //!< INFOG(11)
  double mb_in_core_max = 0, mb_in_core_sum = 0;  //!< INFOG(16), INFOG(17): estimated, factorization in core
  double mb_ooc_max = 0, mb_ooc_sum = 0;          //!< INFOG(26), INFOG(27): estimated, out of core
  double mb_used_max = 0, mb_used_sum = 0;        //!< INFOG(21), INFOG(22): effectively used by the factorization
  //! Per process (rank order), from the analysis: INFO(3), the factor's real entries there, and INFO(15), INFO(17),
  //! the in-core and out-of-core memory estimates, MB. Filled on the first process only.
  std::vector<double> factor_entries_rank, mb_in_core_rank, mb_ooc_rank;
  int negative_pivots = 0;          //!< INFOG(12)
  double min_pivot_ratio = 0;       //!< smallest |d_k| / A_kk over every process (Instance::local_min_pivot)
};

}  // namespace db::mumps

// The 2-ring vertex pattern (upper triangle with the diagonal, CSC) of an edit's soft-constraint unknowns, as
// metis_levers.cpp reads it: int n, int64 nnz, colptr[n + 1], rows[nnz] (then the 1-ring adjacency, unused).
// Built as a temporary experiments/ driver (copy it to experiments/dump_pattern.cpp, build exp_dump_pattern):
//   build/exp_dump_pattern data/edits/armadillo_loop1_whole.edit g104.bin
#include <cstdio>
#include "edit/edit_io.h"
#include "methods/deformer.h"
#include "systems/normal_system.h"
int main(int argc, char** argv) {
  auto e = db::load_edit_case(argv[1]);
  auto adj = db::vertex_adjacency(e.mesh);
  auto unk = db::make_unknowns(db::classify(e.edit, db::ConstraintMode::Soft), 1.0);
  auto pat = db::interaction_pattern(adj, unk);
  FILE* f = std::fopen(argv[2], "wb");
  int n = unk.num_unknowns(); long long nz = pat.rows.size();
  std::fwrite(&n, 4, 1, f); std::fwrite(&nz, 8, 1, f);
  std::fwrite(pat.colptr.data(), 4, n + 1, f); std::fwrite(pat.rows.data(), 4, nz, f);
  int nv = adj.num_vertices(); long long na = adj.nbr.size();
  std::fwrite(&nv, 4, 1, f); std::fwrite(&na, 8, 1, f);
  std::fwrite(adj.off.data(), 4, nv + 1, f); std::fwrite(adj.nbr.data(), 4, na, f);
  std::fwrite(unk.unknown_of.data(), 4, nv, f);
  std::fclose(f);
  std::printf("n %d nnz_upper %lld nv %d adj %lld\n", n, nz, nv, na);
}

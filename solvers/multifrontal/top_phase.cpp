#include "solvers/multifrontal/top_phase.h"

#include <atomic>

#include "solvers/base/resources.h"

namespace db::multifrontal {
namespace {

class TopRun {
 public:
  TopRun(const TopTree& tree, const std::function<std::unique_ptr<TopScratch>()>& scratch, const TopFront& front)
      : tree_(tree), scratch_(scratch), front_(front) {}

  //! The independent top subtrees `subtrees` on `threads` threads: their bins at once (top_shares), each on a
  //! team and a scratch of its own.
  void at_once(const std::vector<int>& subtrees, int threads) {
    const TopShares shares = top_shares(subtrees, tree_.work, threads);
    run_tasks(int(shares.bins.size()), [&](int b) {
      Team team(shares.threads[std::size_t(b)]);
      const std::unique_ptr<TopScratch> scratch = scratch_();
      for (int s : shares.bins[std::size_t(b)]) subtree(s, team, *scratch);
    });
  }

  bool ok() const { return ok_.load(); }

 private:
  //! s's top subtree on `team`, s last. A team of one runs several children one after another itself.
  void subtree(int s, Team& team, TopScratch& scratch) {
    const std::vector<int>& kids = tree_.children[std::size_t(s)];
    if (kids.size() > 1 && team.size() > 1) {
      at_once(kids, team.size());
    } else {
      for (int c : kids) subtree(c, team, scratch);
    }
    if (ok_.load() && !front_(s, team, scratch)) ok_.store(false);
  }

  const TopTree& tree_;
  const std::function<std::unique_ptr<TopScratch>()>& scratch_;
  const TopFront& front_;
  std::atomic<bool> ok_{true};
};

}  // namespace

bool run_top_phase(const TopTree& tree, int threads, const std::function<std::unique_ptr<TopScratch>()>& scratch,
                   const TopFront& front) {
  if (tree.roots.empty()) return true;
  TopRun run(tree, scratch, front);
  run.at_once(tree.roots, threads);
  return run.ok();
}

}  // namespace db::multifrontal

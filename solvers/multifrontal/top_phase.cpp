#include "solvers/multifrontal/top_phase.h"

#include <atomic>
#include <mutex>
#include <utility>
#include <vector>

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
      std::unique_ptr<TopScratch> scratch = take_scratch();
      for (int s : shares.bins[std::size_t(b)]) subtree(s, team, *scratch);
      give_scratch(std::move(scratch));
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

  //! A scratch no bin holds, made only when none is free: no more are made than bins run at once, each a map over
  //! all the unknowns that would otherwise be allocated and filled anew for every bin.
  std::unique_ptr<TopScratch> take_scratch() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<TopScratch> s = std::move(free_.back());
        free_.pop_back();
        return s;
      }
    }
    return scratch_();
  }
  void give_scratch(std::unique_ptr<TopScratch> s) {
    const std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(s));
  }

  const TopTree& tree_;
  const std::function<std::unique_ptr<TopScratch>()>& scratch_;
  const TopFront& front_;
  std::atomic<bool> ok_{true};
  std::mutex mutex_;
  std::vector<std::unique_ptr<TopScratch>> free_;
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

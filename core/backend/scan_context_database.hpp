#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/backend/scan_context.hpp"

namespace dammloam::backend {

struct ScanContextDatabaseConfig {
  int exclude_recent = 30;       // newest entries never returned (they are neighbours in time)
  int num_candidates = 10;       // ring-key nearest neighbours re-ranked by the full distance
  int rebuild_every = 20;        // new entries before the k-d tree is rebuilt (rest: brute force)
  double max_distance = 0.25;    // column-shift distance above which nothing is returned

  bool operator==(const ScanContextDatabaseConfig&) const = default;
};

struct ScanContextCandidate {
  std::uint32_t id = 0;          // index in insertion order
  ScanContextMatch match;
};

// Two-phase retrieval of the paper: ring-key k-d tree (nanoflann) for coarse candidates, then
// the column-shift distance. Not thread-safe; owned by one back-end thread.
class ScanContextDatabase {
 public:
  explicit ScanContextDatabase(const ScanContextDatabaseConfig& config = {});
  ~ScanContextDatabase();
  ScanContextDatabase(ScanContextDatabase&&) noexcept;
  ScanContextDatabase& operator=(ScanContextDatabase&&) noexcept;

  // Appends a descriptor; its id is the previous size(). Throws std::invalid_argument for an
  // empty descriptor or one whose ring count differs from the stored ones.
  std::uint32_t Add(const ScanContext& descriptor);
  // Frees an entry's grid and keeps its id: it is never returned again. For keyframes whose
  // cloud was dropped (a revisit of mapped ground), so memory follows the area, not the time.
  void Retire(std::uint32_t id);
  std::size_t size() const { return descriptors_.size(); }
  const ScanContext& at(std::uint32_t id) const { return descriptors_.at(id); }

  // Best candidates (best first, at most num_candidates) among entries older than the newest
  // exclude_recent ones, with distance <= max_distance.
  std::vector<ScanContextCandidate> Query(const ScanContext& query) const;
  // Same, with an explicit exclusion count (0 for relocalization in a finished map).
  std::vector<ScanContextCandidate> Query(const ScanContext& query, int exclude_recent,
                                          double max_distance) const;

 private:
  struct Tree;
  void RebuildIfStale(std::size_t searchable) const;

  ScanContextDatabaseConfig config_;
  std::vector<ScanContext> descriptors_;
  mutable std::unique_ptr<Tree> tree_;  // rebuilt lazily inside const Query
};

}  // namespace dammloam::backend

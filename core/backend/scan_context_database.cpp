#include "core/backend/scan_context_database.hpp"

#include <algorithm>
#include <nanoflann.hpp>
#include <stdexcept>

namespace dammloam::backend {

// Ring keys copied into one flat array so that nanoflann can read them.
struct ScanContextDatabase::Tree {
  struct Keys {
    std::vector<float> data;
    std::size_t dim = 0;
    std::size_t kdtree_get_point_count() const { return dim == 0 ? 0 : data.size() / dim; }
    float kdtree_get_pt(std::size_t i, std::size_t d) const { return data[i * dim + d]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Keys>,
                                                    Keys, -1, std::uint32_t>;
  Keys keys;
  std::unique_ptr<Index> index;
  std::size_t size() const { return keys.kdtree_get_point_count(); }
};

ScanContextDatabase::ScanContextDatabase(const ScanContextDatabaseConfig& config)
    : config_(config) {}
ScanContextDatabase::~ScanContextDatabase() = default;
ScanContextDatabase::ScanContextDatabase(ScanContextDatabase&&) noexcept = default;
ScanContextDatabase& ScanContextDatabase::operator=(ScanContextDatabase&&) noexcept = default;

std::uint32_t ScanContextDatabase::Add(const ScanContext& descriptor) {
  if (descriptor.empty() ||
      (!descriptors_.empty() && descriptor.ring_key.size() != descriptors_.front().ring_key.size())) {
    throw std::invalid_argument("ScanContextDatabase::Add: descriptor is empty or was made with "
                                "a different ring count than the stored ones");
  }
  descriptors_.push_back(descriptor);
  return static_cast<std::uint32_t>(descriptors_.size() - 1);
}

void ScanContextDatabase::Retire(std::uint32_t id) {
  ScanContext& entry = descriptors_.at(id);
  if (entry.empty()) return;
  entry.grid.resize(0, 0);
  // Far from any real key (occupancy lies in [0, 1]), so the coarse phase passes it over.
  entry.ring_key.setConstant(1e6f);
  if (tree_ && id < tree_->size()) tree_.reset();  // the tree holds the old key
}

void ScanContextDatabase::RebuildIfStale(std::size_t searchable) const {
  const std::size_t built = tree_ ? tree_->size() : 0;
  // Entries past the tree are searched by brute force, so rebuilding is only an optimisation.
  if (tree_ && built <= searchable &&
      searchable < built + static_cast<std::size_t>(std::max(1, config_.rebuild_every))) {
    return;
  }
  auto tree = std::make_unique<Tree>();
  tree->keys.dim = static_cast<std::size_t>(descriptors_.front().ring_key.size());
  tree->keys.data.reserve(searchable * tree->keys.dim);
  for (std::size_t i = 0; i < searchable; ++i) {
    const Eigen::VectorXf& key = descriptors_[i].ring_key;
    tree->keys.data.insert(tree->keys.data.end(), key.data(), key.data() + key.size());
  }
  tree->index = std::make_unique<Tree::Index>(tree->keys.dim, tree->keys,
                                              nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree_ = std::move(tree);
}

std::vector<ScanContextCandidate> ScanContextDatabase::Query(const ScanContext& query) const {
  return Query(query, config_.exclude_recent, config_.max_distance);
}

std::vector<ScanContextCandidate> ScanContextDatabase::Query(const ScanContext& query,
                                                             int exclude_recent,
                                                             double max_distance) const {
  const std::size_t excluded = static_cast<std::size_t>(std::max(0, exclude_recent));
  if (query.empty() || descriptors_.size() <= excluded) return {};
  // Descriptors made under another config are not comparable (and would overrun the tree).
  if (query.ring_key.size() != descriptors_.front().ring_key.size()) return {};
  const std::size_t searchable = descriptors_.size() - excluded;
  RebuildIfStale(searchable);

  // Coarse phase: ring-key neighbours from the tree plus the not-yet-indexed tail.
  const std::size_t k = static_cast<std::size_t>(std::max(1, config_.num_candidates));
  std::vector<std::uint32_t> ids(k);
  std::vector<float> squared(k);
  const std::size_t found =
      tree_->index->knnSearch(query.ring_key.data(), k, ids.data(), squared.data());
  ids.resize(found);
  squared.resize(found);
  std::vector<std::pair<float, std::uint32_t>> coarse;
  for (std::size_t i = 0; i < found; ++i) coarse.emplace_back(squared[i], ids[i]);
  for (std::size_t i = tree_->size(); i < searchable; ++i) {
    coarse.emplace_back((descriptors_[i].ring_key - query.ring_key).squaredNorm(),
                        static_cast<std::uint32_t>(i));
  }
  std::sort(coarse.begin(), coarse.end());
  if (coarse.size() > k) coarse.resize(k);

  // Fine phase: column-shift distance with yaw.
  std::vector<ScanContextCandidate> result;
  for (const auto& [unused, id] : coarse) {
    if (descriptors_[id].empty()) continue;  // retired
    const ScanContextMatch match = CompareScanContexts(query, descriptors_[id]);
    if (match.distance <= max_distance) result.push_back({id, match});
  }
  std::sort(result.begin(), result.end(), [](const auto& a, const auto& b) {
    return a.match.distance < b.match.distance;
  });
  return result;
}

}  // namespace dammloam::backend

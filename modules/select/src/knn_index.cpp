// The only file that includes FLANN (see knn_index.hpp).
#include <flann/flann.hpp>

#include "photoscene/select/knn_index.hpp"

#include <cmath>
#include <stdexcept>

namespace ps {

const char* knnIndexTypeName(KnnIndexType type) {
  switch (type) {
    case KnnIndexType::Linear: return "linear";
    case KnnIndexType::KdTree: return "kdtree";
    case KnnIndexType::KMeans: return "kmeans";
  }
  return "?";
}

struct KnnIndex::Impl {
  std::vector<float> keys;
  int rows = 0, dim = 0;
  KnnIndexType type = KnnIndexType::KdTree;
  std::unique_ptr<flann::Index<flann::L2<float>>> index;
};

namespace {
flann::IndexParams paramsFor(KnnIndexType type) {
  switch (type) {
    case KnnIndexType::Linear: return flann::LinearIndexParams();
    case KnnIndexType::KdTree: return flann::KDTreeIndexParams(4);
    case KnnIndexType::KMeans: return flann::KMeansIndexParams(16, 11, flann::FLANN_CENTERS_KMEANSPP);
  }
  return flann::LinearIndexParams();
}
}  // namespace

KnnIndex::KnnIndex(const std::vector<float>& keys, int rows, int dim, KnnIndexType type)
    : impl_(std::make_unique<Impl>()) {
  if (rows <= 0 || dim <= 0 || keys.size() != static_cast<size_t>(rows) * dim)
    throw std::invalid_argument("KnnIndex: keys must hold rows * dim floats");
  impl_->keys = keys;
  impl_->rows = rows;
  impl_->dim = dim;
  impl_->type = type;
  flann::Matrix<float> data(impl_->keys.data(), rows, dim);
  impl_->index = std::make_unique<flann::Index<flann::L2<float>>>(data, paramsFor(type));
  // seeds FLANN's tree randomisation; the k-d trees still differ from run to run (measured in
  // Select_Knn), which is why the exemplar bank uses the exact (Linear) index
  flann::seed_random(0);
  impl_->index->buildIndex();
}

KnnIndex::~KnnIndex() = default;
KnnIndex::KnnIndex(KnnIndex&&) noexcept = default;
KnnIndex& KnnIndex::operator=(KnnIndex&&) noexcept = default;

int KnnIndex::rows() const { return impl_->rows; }
int KnnIndex::dim() const { return impl_->dim; }
KnnIndexType KnnIndex::type() const { return impl_->type; }

KnnResult KnnIndex::search(const std::vector<float>& query, int k) const {
  if (query.size() != static_cast<size_t>(impl_->dim)) throw std::invalid_argument("KnnIndex: query length");
  k = std::max(1, std::min(k, impl_->rows));
  std::vector<float> q = query;
  flann::Matrix<float> qm(q.data(), 1, impl_->dim);
  std::vector<int> idx(k);
  std::vector<float> dist(k);
  flann::Matrix<int> im(idx.data(), 1, k);
  flann::Matrix<float> dm(dist.data(), 1, k);
  flann::SearchParams params(impl_->type == KnnIndexType::Linear ? flann::FLANN_CHECKS_UNLIMITED : 128);
  params.sorted = true;
  impl_->index->knnSearch(qm, im, dm, k, params);
  KnnResult r;
  for (int i = 0; i < k; ++i) {
    if (idx[i] < 0) continue;
    r.index.push_back(idx[i]);
    r.distance.push_back(std::sqrt(std::max(0.0f, dist[i])));  // FLANN's L2 is squared
  }
  return r;
}

void KnnIndex::save(const std::string& path) const { impl_->index->save(path); }

KnnIndex KnnIndex::load(const std::string& path, const std::vector<float>& keys, int rows, int dim,
                        KnnIndexType type) {
  KnnIndex out;
  out.impl_ = std::make_unique<Impl>();
  out.impl_->keys = keys;
  out.impl_->rows = rows;
  out.impl_->dim = dim;
  out.impl_->type = type;
  flann::Matrix<float> data(out.impl_->keys.data(), rows, dim);
  out.impl_->index = std::make_unique<flann::Index<flann::L2<float>>>(data, flann::SavedIndexParams(path));
  return out;
}

}  // namespace ps

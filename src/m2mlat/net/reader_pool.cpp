// Leasing and returning the read-only stores.
#include "m2mlat/net/reader_pool.hpp"

namespace m2mlat::net {

ReaderPool::Lease ReaderPool::lease() {
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      auto store = std::move(idle_.back());
      idle_.pop_back();
      return Lease(*this, std::move(store));
    }
  }
  store::Options read_only;
  read_only.read_only = true;
  return Lease(*this, std::make_unique<store::Store>(store::Store::open(path_, read_only)));
}

void ReaderPool::give_back(std::unique_ptr<store::Store> store) {
  if (!store) return;
  std::lock_guard lock(mutex_);
  if (idle_.size() < keep_) idle_.push_back(std::move(store));
  // else: closed here, as `store` goes
}

}  // namespace m2mlat::net

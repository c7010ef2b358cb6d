// Read-only stores for the agent's request threads. The server has a thread per connection (not a
// fixed pool), so a store per thread would be opened and left behind by every connection; instead a
// handler leases one for as long as it reads, and gives it back for the next. At most `keep` idle
// stores stay open; a lease beyond them opens one more and closes it on return.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "m2mlat/store/store.hpp"

namespace m2mlat::net {

class ReaderPool {
 public:
  ReaderPool(std::string store_path, std::size_t keep) : path_(std::move(store_path)), keep_(keep) {}

  class Lease {
   public:
    Lease(ReaderPool& pool, std::unique_ptr<store::Store> store) : pool_(pool), store_(std::move(store)) {}
    ~Lease() { pool_.give_back(std::move(store_)); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    store::Store& operator*() const { return *store_; }
    store::Store* operator->() const { return store_.get(); }

   private:
    ReaderPool& pool_;
    std::unique_ptr<store::Store> store_;
  };

  // An open read-only store of the path (throws what store::Store::open throws).
  Lease lease();

 private:
  void give_back(std::unique_ptr<store::Store> store);

  std::string path_;
  std::size_t keep_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<store::Store>> idle_;
};

}  // namespace m2mlat::net

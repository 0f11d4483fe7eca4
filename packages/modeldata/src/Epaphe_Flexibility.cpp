#include "Epaphe_Flexibility.hpp"

#include "Epaphe_Error.hpp"

namespace epaphe {

Flexibility::Flexibility(const DenseMatrix& dense) {
  EPAPHE_REQUIRE(dense.extent(0) == dense.extent(1) && dense.extent(0) > 0,
                 "flexibility: a dense block is " << dense.extent(0) << " x " << dense.extent(1)
                                                  << "; it must be square and not empty");
  size_ = static_cast<int>(dense.extent(0));
  blocks_.push_back(Block{0, size_, dense, DenseVector()});
}

Flexibility Flexibility::diagonal(const DenseVector& d) {
  EPAPHE_REQUIRE(d.extent(0) > 0, "flexibility: an empty diagonal block");
  Flexibility f;
  f.size_ = static_cast<int>(d.extent(0));
  f.blocks_.push_back(Block{0, f.size_, DenseMatrix(), d});
  return f;
}

void Flexibility::append(const Flexibility& next) {
  for (Block b : next.blocks_) {
    b.offset += size_;
    blocks_.push_back(b);
  }
  size_ += next.size_;
}

Flexibility::Packed Flexibility::pack() const {
  Packed p;
  const int nb = numBlocks();
  p.blocks = Kokkos::View<int* [2]>("epaphe::flexibility::blocks", nb);
  p.start = Kokkos::View<std::size_t*>("epaphe::flexibility::start", nb);
  p.diag = Kokkos::View<double*>("epaphe::flexibility::diagonal", size_);
  p.denseRow = Kokkos::View<int*>("epaphe::flexibility::dense_row", size_);
  auto bH = Kokkos::create_mirror_view(p.blocks);
  auto sH = Kokkos::create_mirror_view(p.start);
  auto dH = Kokkos::create_mirror_view(p.diag);
  auto rH = Kokkos::create_mirror_view(p.denseRow);
  std::size_t denseEntries = 0;
  for (const Block& b : blocks_)
    if (b.dense.extent(0) > 0) denseEntries += static_cast<std::size_t>(b.size) * b.size;
  LargeTable dense = largeTable("epaphe::flexibility::dense", denseEntries);
  p.dense = dense.view;
  p.memory = dense.memory;
  auto fH = Kokkos::create_mirror_view(p.dense);
  std::size_t start = 0;
  for (int ib = 0; ib < nb; ++ib) {
    const Block& b = blocks_[ib];
    bH(ib, 0) = b.offset;
    bH(ib, 1) = b.size;
    sH(ib) = start;
    if (b.dense.extent(0) == 0) {
      auto d = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.diag);
      for (int i = 0; i < b.size; ++i) {
        dH(b.offset + i) = d(i);
        rH(b.offset + i) = -1;
      }
      continue;
    }
    auto F = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.dense);
    for (int j = 0; j < b.size; ++j)
      for (int i = 0; i < b.size; ++i) fH(start + static_cast<std::size_t>(j) * b.size + i) = F(i, j);
    for (int i = 0; i < b.size; ++i) {
      dH(b.offset + i) = 0.0;
      rH(b.offset + i) = p.denseRows++;
    }
    start += static_cast<std::size_t>(b.size) * b.size;
  }
  Kokkos::deep_copy(p.blocks, bH);
  Kokkos::deep_copy(p.start, sH);
  Kokkos::deep_copy(p.diag, dH);
  Kokkos::deep_copy(p.denseRow, rH);
  Kokkos::deep_copy(p.dense, fH);
  return p;
}

}  // namespace epaphe

#pragma once
// The system flexibility F = (M/h^2 + D/2h)^{-1} that the contact correction reads (thesis eqs.
// 2.32 and 2.35), block diagonal over the bodies whose coordinates are stacked in the system q.
// A reduced body's block is dense (size^2 entries). A full body with lumped mass and no or
// mass-proportional damping has a diagonal M/h^2 + D/2h, hence a diagonal block (size entries):
// its part of F D^T and of the correction F G lambda is a scaling of the entries of D, with no
// N x N storage anywhere.
#include "Epaphe_DenseTypes.hpp"
#include "Epaphe_Parallel.hpp"

#include <Kokkos_Core.hpp>

#include <memory>
#include <vector>

namespace epaphe {

/// The system flexibility F, block diagonal over the bodies: dense or diagonal blocks (see the file's
/// opening comment).
class Flexibility {
public:
  Flexibility() = default;
  /// One dense block, F of a reduced body (n x n, symmetric). Implicit: a dense F is a one-block
  /// flexibility.
  Flexibility(const DenseMatrix& dense);  // NOLINT(google-explicit-constructor)
  /// One diagonal block: F = diag(d).
  static Flexibility diagonal(const DenseVector& d);
  /// Appends the blocks of `next` after this one's: the flexibility of the two systems stacked.
  void append(const Flexibility& next);

  /// The system's size (the rows of F).
  int size() const { return size_; }
  /// The number of blocks (bodies).
  int numBlocks() const { return static_cast<int>(blocks_.size()); }
  /// The first system row of block `b`.
  int offset(int b) const { return blocks_[b].offset; }
  /// The size of block `b`.
  int blockSize(int b) const { return blocks_[b].size; }

  /// What the contact kernels read, copied into them by value. The rows of the dense blocks are
  /// numbered consecutively ("dense rows").
  struct Packed {
    Kokkos::View<int* [2]> blocks;     ///< per block: offset, size
    Kokkos::View<std::size_t*> start;  ///< per block: where its entries start in `dense` (dense blocks)
    Kokkos::View<double*> dense;       ///< the dense blocks, each column-major, one after the other
    Kokkos::View<double*> diag;        ///< per system row: F_ii of a diagonal block (0 in a dense block)
    Kokkos::View<int*> denseRow;       ///< per system row: its dense row, or -1 in a diagonal block
    int denseRows = 0;                 ///< the rows of all dense blocks
    std::shared_ptr<void> memory;      ///< keeps `dense` (a LargeTable, Epaphe_Parallel.hpp); empty in a copy

    /// The system's size.
    int size() const { return static_cast<int>(denseRow.extent(0)); }
    /// The same views, unmanaged (Epaphe_Parallel.hpp: unmanaged): what a step copies into its
    /// kernels, counting no references (no `memory` either); this Packed keeps the memory.
    Packed untracked() const {
      return Packed{unmanaged(blocks),   unmanaged(start), unmanaged(dense), unmanaged(diag),
                    unmanaged(denseRow), denseRows,        nullptr};
    }
  };
  /// The packed copy (built at each call: at setup).
  Packed pack() const;

private:
  struct Block {
    int offset = 0, size = 0;
    DenseMatrix dense;  ///< empty for a diagonal block
    DenseVector diag;
  };
  std::vector<Block> blocks_;
  int size_ = 0;
};

}  // namespace epaphe

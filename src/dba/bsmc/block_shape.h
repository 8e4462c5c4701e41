// One dispatch from a block's run-time shape to compile-time sizes, for the
// kernels over BSMC blocks (the symmetric product, block-Jacobi): the shapes
// of the two camera models get fixed-size code (Eigen keeps the block in
// registers and unrolls), any other shape the dynamic-size fallback.
//
//   BAL            camera x camera        9 x 9
//   photogrammetric pose x pose           6 x 6
//                   pose x intrinsics     6 x 5 (all five free)
//                   intrinsics x intrinsics 5 x 5
//
// Usage: WithBlockShape(r, c, [&]<int R, int C>() { ... Eigen::Matrix<double,
// R, C> ... }); R and C are Eigen::Dynamic for other shapes. Square blocks:
// WithSquareBlockSize(n, [&]<int N>() { ... }).
// Thread safety: pure.
#pragma once

#include <Eigen/Core>

namespace dba {

template <typename F>
inline void WithBlockShape(int rows, int cols, F&& f) {
  if (rows == 9 && cols == 9) {
    f.template operator()<9, 9>();
  } else if (rows == 6 && cols == 6) {
    f.template operator()<6, 6>();
  } else if (rows == 6 && cols == 5) {
    f.template operator()<6, 5>();
  } else if (rows == 5 && cols == 5) {
    f.template operator()<5, 5>();
  } else {
    f.template operator()<Eigen::Dynamic, Eigen::Dynamic>();
  }
}

// The same for a square (diagonal) block of size n: f.template operator()<N>()
// with N 9, 6 or 5, else Eigen::Dynamic.
template <typename F>
inline void WithSquareBlockSize(int n, F&& f) {
  if (n == 9) {
    f.template operator()<9>();
  } else if (n == 6) {
    f.template operator()<6>();
  } else if (n == 5) {
    f.template operator()<5>();
  } else {
    f.template operator()<Eigen::Dynamic>();
  }
}

}  // namespace dba

// The BAL residual and Jacobians of camera/bal_camera.h (the same formulas)
// for four observations of one point at once, one per SIMD lane.
//
// One observation's kernel is about 150 flops in a chain of dependent
// scalar operations (a division, then the distortion, then ∂u/∂P, then the
// rotation's columns); the compiler packs at most two of them per
// instruction and spills. Four observations in the four lanes of a vector
// register (GCC's vector extensions: AVX2 on x86-64-v3, plain SSE or scalar
// code elsewhere) do the same arithmetic in a quarter of the instructions.
//
// Thread safety: pure functions over caller-owned memory.
#pragma once

#include "dba/camera/rotation.h"

namespace dba {

// For each lane l: the residual (2 values), ∂r/∂c (2 x 9 row-major, 18
// values) and ∂r/∂X (2 x 3 row-major, 6 values) of observation `pixel[l]`
// of the point X by the camera with parameters camera[l] (9 values) and
// rotation frame frame[l], written to r[l], J_c[l] and J_p[l].
void BalResidualsAndJacobians(const RotationFrame* const frame[4], const double* const camera[4],
                              const double* const pixel[4], const double* X, double* const r[4],
                              double* const J_c[4], double* const J_p[4]);

}  // namespace dba

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

#include <cstdint>

#include "dba/camera/rotation.h"
#include "dba/camera/rotation_frame_cache.h"

namespace dba {

// For each lane l: the residual (2 values), ∂r/∂c (2 x 9 row-major, 18
// values) and ∂r/∂X (2 x 3 row-major, 6 values) of observation `pixel[l]`
// of the point X by the camera with parameters camera[l] (9 values) and
// rotation frame frame[l], written to r[l], J_c[l] and J_p[l]. With J_c and
// J_p null, the residuals only.
void BalResidualsAndJacobians(const RotationFrame* const frame[4], const double* const camera[4],
                              const double* const pixel[4], const double* X, double* const r[4],
                              double* const J_c[4], double* const J_p[4]);

// The m observations of one point X, four at a time: observation a by
// camera obs_camera[a] (parameters cameras + 9 obs_camera[a], its rotation
// frame from `frames`) at pixel obs_pixel + 2a. Writes r[a], and J_c[a],
// J_p[a] unless J_c is null (residuals only). Lanes past the last
// observation repeat it into scratch; a camera whose cache slot a later lane
// of the four took gets its frame recomputed.
void BalPointResiduals(const int32_t* obs_camera, const double* obs_pixel, const double* cameras,
                       RotationFrameCache* frames, int m, const double* X, Vec2* r,
                       BalCameraJacobian* J_c, PointJacobian* J_p);

}  // namespace dba

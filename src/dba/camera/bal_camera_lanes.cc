// The BAL kernel on four lanes; see bal_camera_lanes.h, and bal_camera.h for
// the formulas (the scalar BalResidualAndJacobians computes the same values).
#include "dba/camera/bal_camera_lanes.h"

#include "dba/camera/bal_kernel.h"

#include <algorithm>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace dba {
namespace {

typedef double V __attribute__((vector_size(32)));

// p[l][0..3] = a[l], b[l], c[l], d[l] for each lane l: a 4x4 transpose.
inline void StoreTransposed(V a, V b, V c, V d, double* const p[4], int offset) {
#if defined(__AVX__)
  const __m256d ab_lo = _mm256_unpacklo_pd(a, b);  // a0 b0 a2 b2
  const __m256d ab_hi = _mm256_unpackhi_pd(a, b);  // a1 b1 a3 b3
  const __m256d cd_lo = _mm256_unpacklo_pd(c, d);
  const __m256d cd_hi = _mm256_unpackhi_pd(c, d);
  _mm256_storeu_pd(p[0] + offset, _mm256_permute2f128_pd(ab_lo, cd_lo, 0x20));
  _mm256_storeu_pd(p[1] + offset, _mm256_permute2f128_pd(ab_hi, cd_hi, 0x20));
  _mm256_storeu_pd(p[2] + offset, _mm256_permute2f128_pd(ab_lo, cd_lo, 0x31));
  _mm256_storeu_pd(p[3] + offset, _mm256_permute2f128_pd(ab_hi, cd_hi, 0x31));
#else
  for (int l = 0; l < 4; ++l) {
    p[l][offset] = a[l], p[l][offset + 1] = b[l], p[l][offset + 2] = c[l],
    p[l][offset + 3] = d[l];
  }
#endif
}

// a[l], b[l], c[l], d[l] = p[l][offset..offset+3] for each lane l.
inline void LoadTransposed(const double* const p[4], int offset, V* a, V* b, V* c, V* d) {
#if defined(__AVX__)
  const __m256d r0 = _mm256_loadu_pd(p[0] + offset), r1 = _mm256_loadu_pd(p[1] + offset);
  const __m256d r2 = _mm256_loadu_pd(p[2] + offset), r3 = _mm256_loadu_pd(p[3] + offset);
  const __m256d lo01 = _mm256_unpacklo_pd(r0, r1);  // p0[0] p1[0] p0[2] p1[2]
  const __m256d hi01 = _mm256_unpackhi_pd(r0, r1);  // p0[1] p1[1] p0[3] p1[3]
  const __m256d lo23 = _mm256_unpacklo_pd(r2, r3);
  const __m256d hi23 = _mm256_unpackhi_pd(r2, r3);
  *a = _mm256_permute2f128_pd(lo01, lo23, 0x20);
  *b = _mm256_permute2f128_pd(hi01, hi23, 0x20);
  *c = _mm256_permute2f128_pd(lo01, lo23, 0x31);
  *d = _mm256_permute2f128_pd(hi01, hi23, 0x31);
#else
  for (int l = 0; l < 4; ++l) {
    (*a)[l] = p[l][offset], (*b)[l] = p[l][offset + 1], (*c)[l] = p[l][offset + 2],
    (*d)[l] = p[l][offset + 3];
  }
#endif
}

inline V Gather(const double* const p[4], int offset) {
  return V{p[0][offset], p[1][offset], p[2][offset], p[3][offset]};
}

// p[l][offset], p[l][offset + 1] = a[l], b[l]: one 16-byte store per lane,
// so that a reader loading the pair as one vector (a Vec2, a row of J_p)
// gets it forwarded from the store; two 8-byte stores cannot be, and that
// stall was most of the caller's time.
inline void StorePair(V a, V b, double* const p[4], int offset) {
#if defined(__AVX__)
  const __m256d lo = _mm256_unpacklo_pd(a, b);  // a0 b0 a2 b2
  const __m256d hi = _mm256_unpackhi_pd(a, b);  // a1 b1 a3 b3
  _mm_storeu_pd(p[0] + offset, _mm256_castpd256_pd128(lo));
  _mm_storeu_pd(p[1] + offset, _mm256_castpd256_pd128(hi));
  _mm_storeu_pd(p[2] + offset, _mm256_extractf128_pd(lo, 1));
  _mm_storeu_pd(p[3] + offset, _mm256_extractf128_pd(hi, 1));
#else
  for (int l = 0; l < 4; ++l) p[l][offset] = a[l], p[l][offset + 1] = b[l];
#endif
}

}  // namespace

void BalResidualsAndJacobians(const RotationFrame* const frame[4], const double* const camera[4],
                              const double* const pixel[4], const double* X, double* const r[4],
                              double* const J_c[4], double* const J_p[4]) {
  // A frame is R then J_l, each column-major (R(i, j) = R[i + 3 j]): 18
  // doubles, read as four 4x4 transposes and two gathers.
  static_assert(sizeof(RotationFrame) == 18 * sizeof(double));
  const double* const fp[4] = {frame[0]->R.data(), frame[1]->R.data(), frame[2]->R.data(),
                               frame[3]->R.data()};
  V R[9], L[9];
  LoadTransposed(fp, 0, &R[0], &R[1], &R[2], &R[3]);
  LoadTransposed(fp, 4, &R[4], &R[5], &R[6], &R[7]);
  LoadTransposed(fp, 8, &R[8], &L[0], &L[1], &L[2]);
  V t0, t1, t2, f, k1, k2;
  LoadTransposed(camera, 3, &t0, &t1, &t2, &f);
  LoadTransposed(camera, 5, &t2, &f, &k1, &k2);
  const V t[3] = {t0, t1, t2};
  const V u[2] = {Gather(pixel, 0), Gather(pixel, 1)};
  V res[2];
  if (J_c == nullptr) {
    BalKernel<V>(R, L, t, f, k1, k2, u, X, res, nullptr, nullptr);
    StorePair(res[0], res[1], r, 0);
    return;
  }
  LoadTransposed(fp, 12, &L[3], &L[4], &L[5], &L[6]);
  L[7] = Gather(fp, 16), L[8] = Gather(fp, 17);
  V Jc[2][9], Jp[2][3];
  BalKernel(R, L, t, f, k1, k2, u, X, res, Jc, Jp);
  StorePair(res[0], res[1], r, 0);
  // J_c row-major: values 0..8 row 0, 9..17 row 1.
  const V* jc = &Jc[0][0];
  StoreTransposed(jc[0], jc[1], jc[2], jc[3], J_c, 0);
  StoreTransposed(jc[4], jc[5], jc[6], jc[7], J_c, 4);
  StoreTransposed(jc[8], jc[9], jc[10], jc[11], J_c, 8);
  StoreTransposed(jc[12], jc[13], jc[14], jc[15], J_c, 12);
  StorePair(jc[16], jc[17], J_c, 16);
  StoreTransposed(Jp[0][0], Jp[0][1], Jp[0][2], Jp[1][0], J_p, 0);
  StorePair(Jp[1][1], Jp[1][2], J_p, 4);
}

void BalPointResiduals(const int32_t* obs_camera, const double* obs_pixel, const double* cameras,
                       RotationFrameCache* frames, int m, const double* X, Vec2* r,
                       BalCameraJacobian* J_c, PointJacobian* J_p) {
  double pad_r[2], pad_J_c[18], pad_J_p[6];
  RotationFrame own[4];
  const RotationFrame* frame[4];
  const double *camera[4], *pixel[4];
  double *rl[4], *J_cl[4], *J_pl[4];
  for (int a0 = 0; a0 < m; a0 += 4) {
    for (int l = 0; l < 4; ++l) {
      const int a = std::min(a0 + l, m - 1);
      camera[l] = cameras + 9 * int64_t{obs_camera[a]};
      pixel[l] = obs_pixel + 2 * a;
      frame[l] = &frames->Get(obs_camera[a], camera[l]);
      const bool real = a0 + l < m;
      rl[l] = real ? r[a].data() : pad_r;
      if (J_c != nullptr) {
        J_cl[l] = real ? J_c[a].data() : pad_J_c;
        J_pl[l] = real ? J_p[a].data() : pad_J_p;
      }
    }
    for (int l = 0; l < 3; ++l) {
      const int32_t i = obs_camera[std::min(a0 + l, m - 1)];
      if (!frames->Holds(i)) own[l] = MakeRotationFrame(camera[l]), frame[l] = &own[l];
    }
    BalResidualsAndJacobians(frame, camera, pixel, X, rl, J_c != nullptr ? J_cl : nullptr,
                             J_c != nullptr ? J_pl : nullptr);
  }
}

}  // namespace dba

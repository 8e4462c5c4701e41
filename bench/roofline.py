#!/usr/bin/env python3
"""Roofline of dba's three per-iteration phases, from a solve's report.

  python3 bench/roofline.py PROBLEM.dba REPORT.json [PROBLEM.dba REPORT.json ...]
      [--gflops 102] [--bandwidth 24.4]

PROBLEM.dba is the solved problem (BAL model: 9-parameter cameras), read for
its track lengths; REPORT.json is `dba solve PROBLEM.dba --report` (any
options). Prints one Markdown row per phase and problem: work per pass
(flops and bytes, per observation and in all), seconds per pass, achieved
GFLOP/s and GB/s, the floor (compute and memory) and the ratio of the time
to the larger floor.

Machine limits (bench/README.md, "Roofline"): 102 GFLOP/s (2 cores, AVX2
FMA on doubles) and 24.4 GB/s (STREAM triad, 2 threads). The flops are
counted from the kernels' shapes, not measured (the VM has no counters):

  formation, per observation: residual and Jacobians 150, V and g_p 50,
    K = J_p V_λ⁻¹ 36, the observation's right-hand side, gradient and
    diagonal 110; per pair of a point's observations (Σ_k t_k(t_k+1)/2, t_k
    the track lengths): M_ab 24, the row coefficients J_aᵀ M_ab 54 and the
    rank-2 update of the 9x9 block 324 (rcs/eliminate_point.h, eq. 4).
    Bytes: S's values written and read once per pass (zeroing, then the
    updates), the observations (camera index and pixel, 20 bytes) and the
    points once.
  back-substitution, per observation: residual and Jacobians 150, V and g_p
    50, J_c δc 36, J_pᵀ r 12, the model residual 12, the candidate's
    residual 40. Bytes: the observations twice (current and candidate),
    the points read and the candidate points written.
  PCG, per iteration: one product streaming S (mixed precision: diagonal
    blocks in double, the others in float), its structure and four vectors
    of the unknowns; the seconds per iteration include the preconditioner's
    set-up once per LM iteration, spread over its PCG iterations.
"""
import json
import struct
import sys
from array import array


def track_lengths(path):
    with open(path, 'rb') as f:
        h = f.read(128)
        if h[:8] != b'DBAPROB\n':
            sys.exit(f'{path}: not a dba binary problem')
        points = struct.unpack_from('<Q', h, 32)[0]
        point_offsets_at = struct.unpack_from('<Q', h, 48 + 16)[0]
        f.seek(point_offsets_at)
        offsets = array('Q')
        offsets.frombytes(f.read(8 * (points + 1)))
    return [offsets[k + 1] - offsets[k] for k in range(points)]


def main(argv):
    gflops, bandwidth = 102.0, 24.4
    args = []
    i = 0
    while i < len(argv):
        if argv[i] == '--gflops':
            gflops = float(argv[i + 1]); i += 2
        elif argv[i] == '--bandwidth':
            bandwidth = float(argv[i + 1]); i += 2
        else:
            args.append(argv[i]); i += 1
    if not args or len(args) % 2:
        sys.exit(__doc__)
    print('| problem | phase | passes | flops / obs | bytes / obs | work per pass | s per pass '
          '| GFLOP/s | GB/s | floor compute / memory (ms) | time / floor |')
    print('|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|')
    for problem, report in zip(args[::2], args[1::2]):
        r = json.load(open(report))
        tracks = track_lengths(problem)
        obs, points = sum(tracks), len(tracks)
        pairs = sum(t * (t + 1) // 2 for t in tracks)
        name = problem.rsplit('/', 1)[-1]
        s, m = r['seconds'], r['memory']
        its = r['iterations']
        formations = its + (r['termination'] in ('max_iterations', 'gradient_tolerance'))
        rows = []
        # Formation.
        flops = 346 * obs + 402 * pairs
        byts = 2 * m['rcs_bsmc_value_bytes'] + 20 * obs + 24 * points
        rows.append(('RCS formation', formations, s['rcs_formation'] / formations, flops, byts))
        # Back-substitution.
        flops = 300 * obs
        byts = 40 * obs + 48 * points
        rows.append(('back-substitution', its, s['back_substitution'] / its, flops, byts))
        # PCG.
        if r['pcg_iterations'] > 0:
            cameras = r['num_cameras']
            blocks = m['rcs_blocks']
            unknowns = r['camera_unknowns']
            byts = (cameras * 648 + (blocks - cameras) * 324 + m['rcs_bsmc_structure_bytes'] +
                    4 * 8 * unknowns)
            rows.append(('PCG iteration', r['pcg_iterations'],
                         s['linear_solve'] / r['pcg_iterations'], 0, byts))
        for phase, passes, sec, flops, byts in rows:
            compute = flops / (gflops * 1e9)
            memory = byts / (bandwidth * 1e9)
            floor = max(compute, memory)
            work = (f'{flops / 1e9:.2f} Gflop, ' if flops else '') + f'{byts / 1e6:.0f} MB'
            print(f'| {name} | {phase} | {passes} | {flops / obs:.0f} | {byts / obs:.1f} | {work} | '
                  f'{sec:.3f} | {flops / sec / 1e9:.1f} | {byts / sec / 1e9:.1f} | '
                  f'{compute * 1e3:.0f} / {memory * 1e3:.0f} | {sec / floor:.1f}x |')
    print()
    print(f'Tracks: ' + '; '.join(
        f'{p.rsplit("/", 1)[-1]} {sum(t) / len(t):.2f} per point, '
        f'{sum(x * (x + 1) // 2 for x in t) / sum(t):.2f} pairs per observation'
        for p, t in ((p, track_lengths(p)) for p in args[::2])))


if __name__ == '__main__':
    main(sys.argv[1:])

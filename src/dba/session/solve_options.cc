// The options of a solve: help and parser; see solve_options.h.
#include "dba/session/solve_options.h"

#include <iostream>
#include <stdexcept>
#include <thread>

#include "dba/common/arguments.h"
#include "dba/common/error.h"
#include "dba/rcs/robust_loss.h"
#include "dba/session/solve_option_table.h"

namespace dba {

#ifdef DBA_HAVE_CHOLMOD
#define DBA_SPARSE_NAME "CHOLMOD"
#else
#define DBA_SPARSE_NAME "Eigen"
#endif

int DefaultThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

void PrintSolveHelp(std::ostream& out) {
  out << "Usage: dba solve INPUT [options]\n"
         "\n"
         "Bundle-adjusts INPUT with exact Levenberg-Marquardt: the reduced camera\n"
         "system is formed point by point in BSMC and solved by a dense or sparse\n"
         "Cholesky factorization or by truncated-Newton PCG, whichever is cheapest.\n"
         "Prints one line per iteration and a summary.\n"
         "\n"
         "INPUT is a BAL problem (plain text or .bz2; 9 parameters per camera), a dba\n"
         "binary problem (.dba; BAL cameras, or poses and shared intrinsics, e.g. from\n"
         "dba generate --model photo), or a COLMAP sparse model directory (cameras, images,\n"
         "points3D as .txt or .bin; e.g. project/sparse/0). A COLMAP model is solved\n"
         "in the photogrammetric model: per image a pose (6 unknowns), per physical\n"
         "camera an intrinsic group in its COLMAP camera model (all of COLMAP's; see\n"
         "--list-camera-models) shared by its images. Points with fewer than 2\n"
         "observations are not adjusted.\n"
         "\n"
         "Distributed: started by mpirun or srun with N ranks, the points are split\n"
         "over the ranks, each forms its sub-RCS, and the RCS is spread over the ranks\n"
         "(PCG) or summed on rank 0 (a factorization).\n"
         "\n"
         "Options:\n";
  PrintOptions(SolveOptionTable(), SolveOptions(), out);
  out << "  --list-camera-models       print the lens models and their parameter names\n"
         "  -h, --help                 this text\n"
         "  --                         ends the options: what follows is INPUT (a path\n"
         "                             may start with '-')\n"
         "\n"
         "Outputs (-o, --report, --ply, --checkpoint, --camera-centres,\n"
         "--accuracy-report) are checked before the solve. A file, or a path that does\n"
         "not exist yet, is written to a temporary beside it and renamed over it: the\n"
         "run's outputs appear together when all are written, or none does. A symbolic\n"
         "link is written through (the file it leads to is replaced, the link kept). A\n"
         "character device or a FIFO (/dev/null, a pipe) is written plainly. Anything\n"
         "else (a directory, a socket, /proc) is refused, and so is an output naming an\n"
         "input or another output, except -o over the problem it reads (a COLMAP model\n"
         "replaced whole) and --checkpoint F --resume F.\n"
         "\n"
         "Exit status: 0 on success (whatever the termination reason), 1 on bad\n"
         "input or failure, 2 on bad arguments (outputs refused by the rule above\n"
         "included).\n";
}

SolveOptions ParseSolveArguments(const std::vector<std::string>& args, bool* help) {
  SolveOptions o;
  o.lm.num_threads = 0;  // auto: the node's cores divided by its ranks
  ParseOptions(
      SolveOptionTable(), args, &o,
      [&](const std::string& a) {
        if (!o.input.empty()) {
          throw std::invalid_argument("more than one input file: '" + o.input + "' and '" + a +
                                      "'");
        }
        o.input = a;
      },
      help, "solve");
  if (*help) return o;
  if (o.input.empty()) throw std::invalid_argument("missing INPUT (see dba solve --help)");
  // Rejection without a loss starts robust (the scale --loss-scale's if given).
  if (o.reject_outliers_px > 0 && !o.loss_given) {
    const double scale = o.lm.loss.scale;
    o.lm.loss = RejectionStartLoss(o.reject_outliers_px);
    if (o.loss_scale_given) o.lm.loss.scale = scale;
  }
  // --rcs distributed with what it cannot hold: refused now, as the ranks
  // would (ChooseRcsPlacement's rule, whatever the rank count).
  DistributedOptions d = o.distributed;
  d.lever_arm_row = o.geo.refine_lever_arm;
  ChooseRcsPlacement(d, o.lm, 2);
  return o;
}


}  // namespace dba

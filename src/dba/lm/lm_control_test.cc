// The LM step control alone: SolveLevenbergMarquardt driven by a scripted
// PointWorkers. The fake hands out a small RCS (two free BAL cameras) and, for
// each step, the costs the script says (so the gain ratio ρ is exact), and
// records every call. The tests pin the λ/ν sequence (Nielsen's update),
// accept/reject, what happens to the cameras and the points (FinishStep), the
// history and every termination reason.
//
// Nothing here depends on how the loop computes δ: the tests look at the λ
// passed to FormRcs and EvaluateStep, at the candidate the loop builds from
// the δc it passes, and at costs and norms that the fake makes up.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/common/interrupt.h"
#include "dba/lm/levenberg_marquardt.h"
#include "dba/lm/point_workers.h"
#include "dba/rcs/form_rcs.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// What the workers report for one step, relative to the current cost F:
// L(δ) = F - predicted, F(x + δ) = F - actual, so ρ = actual / predicted.
// With use_candidate_cost, `candidate_cost` replaces F - actual (NaN, ±inf).
struct Step {
  double predicted = 1.0;
  double actual = 1.0;
  double point_step_squared_norm = 1.0;  // |δX|²: keeps ‖δ‖ far from tolerance
  double points_m2 = 1.0;  // Σ |X - X̄|²
  double candidate_cost = kNaN;
  bool use_candidate_cost = false;
};

Step Rho(double rho) { return Step{10.0, 10.0 * rho}; }
Step Rising() { return Step{10.0, -5.0}; }  // F(x + δ) > F(x)
Step CandidateCost(double c) {
  Step s;
  s.candidate_cost = c;
  s.use_candidate_cost = true;
  return s;
}

// What the workers report at one linearization (FormRcs call).
struct Linearization {
  double camera_side_gradient = 1.0;  // max |g_c| (entries ±this and ±half of it)
  double point_gradient = 1.0;   // ‖g_p‖∞
  double rhs_scale = 1.0;        // scale of b, so δc ∝ this
};

class ScriptedWorkers : public PointWorkers {
 public:
  // `cameras` is the LM loop's camera vector, read (never written) to see what
  // the loop holds at each call.
  ScriptedWorkers(double initial_cost, std::vector<Step> steps,
                  const std::vector<double>* cameras)
      : cost_(initial_cost), steps_(std::move(steps)), cameras_(cameras) {
    Problem problem;
    problem.cameras.assign(2 * kBalCameraSize, 0.0);
    layout_ = UnknownLayout(problem);
  }

  // Linearizations for the FormRcs calls in order; the last one repeats.
  void set_linearizations(std::vector<Linearization> l) { linearizations_ = std::move(l); }

  RcsSystem& FormRcs(double lambda) override {
    EXPECT_FALSE(pending_) << "FormRcs before FinishStep of step " << evaluated_.size();
    form_lambdas_.push_back(lambda);
    const Linearization lin =
        linearizations_.empty()
            ? Linearization{}
            : linearizations_[std::min(form_lambdas_.size(), linearizations_.size()) - 1];
    // A fresh system every call, as the real workers refill theirs: S is
    // undamped in the camera blocks and the loop damps it.
    const std::vector<uint64_t> pattern = {PackBlock(0, 0), PackBlock(0, 1), PackBlock(1, 1)};
    system_ = RcsSystem::ForPattern(layout_, pattern);
    // Diagonal S (the off-diagonal block is stored but zero), so that the
    // damped system has the exact solution δ_i = b_i / (S_ii + λ D_ii) that
    // any linear solver finds.
    for (int32_t r = 0; r < 2; ++r) {
      double* block = system_.S.block_values(system_.S.diagonal_block(r));
      for (int d = 0; d < kBalCameraSize; ++d) block[d * kBalCameraSize + d] = Sii(r, d);
    }
    for (int64_t i = 0; i < system_.S.num_rows(); ++i) {
      system_.b[i] = lin.rhs_scale * B(i);
      system_.camera_side_gradient[i] = (i % 3 == 0 ? -1.0 : 0.5) * lin.camera_side_gradient;
      system_.camera_side_jtj_diagonal[i] = Dii(i);
    }
    system_.max_abs_point_gradient = lin.point_gradient;
    system_.cost = cost_;
    return system_;
  }

  // The candidate: the workers' cameras (the loop's, as it holds them) ⊞ δc.
  StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c) override {
    EXPECT_FALSE(pending_) << "two EvaluateStep calls without FinishStep";
    pending_ = true;
    const size_t i = evaluated_.size();
    eval_lambdas_.push_back(lambda);
    lambda_of_last_form_.push_back(form_lambdas_.empty() ? kNaN : form_lambdas_.back());
    cameras_at_eval_.push_back(*cameras_);
    candidates_.emplace_back(cameras_->size());
    layout_.PlusCameraSide(cameras_->data(), delta_c.data(), candidates_.back().data());
    deltas_.push_back(delta_c);
    if (i >= steps_.size()) {
      ADD_FAILURE() << "the loop took step " << i + 1 << ", the script has " << steps_.size();
      evaluated_.push_back(Step{1.0, -1.0});  // reject anything unscripted
    } else {
      evaluated_.push_back(steps_[i]);
    }
    const Step& s = evaluated_.back();
    StepEvaluation e;
    e.model_cost = cost_ - s.predicted;
    e.candidate_cost = s.use_candidate_cost ? s.candidate_cost : cost_ - s.actual;
    e.point_step_squared_norm = s.point_step_squared_norm;
    e.point_spread.m2 = s.points_m2;
    pending_candidate_cost_ = e.candidate_cost;
    return e;
  }

  void FinishStep(bool accept) override {
    EXPECT_TRUE(pending_) << "FinishStep without a step";
    pending_ = false;
    finished_.push_back(accept);
    if (accept) cost_ = pending_candidate_cost_;  // the candidate points become current
  }

  // S_ii (undamped) and diag(JᵀJ), both > DampingBounds::min_diagonal.
  static double Sii(int32_t row, int d) { return 2.0 + row + 0.25 * d; }
  static double Dii(int64_t i) { return 1.0 + 0.5 * static_cast<double>(i); }
  // b for rhs_scale 1.
  static double B(int64_t i) { return (i % 2 == 0 ? 1.0 : -0.5) * (1.0 + 0.1 * static_cast<double>(i)); }

  const UnknownLayout& layout() const { return layout_; }
  double cost() const { return cost_; }
  bool pending() const { return pending_; }
  const std::vector<double>& form_lambdas() const { return form_lambdas_; }
  const std::vector<double>& eval_lambdas() const { return eval_lambdas_; }
  const std::vector<double>& lambda_of_last_form() const { return lambda_of_last_form_; }
  const std::vector<std::vector<double>>& cameras_at_eval() const { return cameras_at_eval_; }
  const std::vector<std::vector<double>>& candidates() const { return candidates_; }
  const std::vector<std::vector<double>>& deltas() const { return deltas_; }
  const std::vector<bool>& finished() const { return finished_; }
  size_t steps_taken() const { return evaluated_.size(); }

 private:
  double cost_;
  std::vector<Step> steps_;
  const std::vector<double>* cameras_;
  UnknownLayout layout_;
  RcsSystem system_;
  std::vector<Linearization> linearizations_;
  bool pending_ = false;
  double pending_candidate_cost_ = 0.0;
  std::vector<Step> evaluated_;
  std::vector<double> form_lambdas_, eval_lambdas_, lambda_of_last_form_;
  std::vector<std::vector<double>> cameras_at_eval_, candidates_, deltas_;
  std::vector<bool> finished_;
};

std::vector<double> InitialCameras() {
  std::vector<double> c(2 * kBalCameraSize);
  for (size_t i = 0; i < c.size(); ++i) c[i] = 1.0 + 0.125 * static_cast<double>(i);
  return c;
}

LmOptions Options() {
  LmOptions o;
  o.initial_lambda = 1.0;
  o.max_iterations = 100;
  o.function_tolerance = 1e-9;
  o.gradient_tolerance = 1e-12;
  o.parameter_tolerance = 1e-10;
  o.max_lambda = 1e16;
  o.min_relative_decrease = 1e-3;
  return o;
}

struct LmRun {
  std::vector<double> cameras = InitialCameras();
  LmSummary summary;
  std::vector<IterationSummary> callbacks;
};

// Runs the loop on `workers` (which must watch run->cameras).
void Solve(const LmOptions& options, ScriptedWorkers* workers, LmRun* run) {
  run->summary = SolveLevenbergMarquardt(options, 1000, &run->cameras, workers,
                                         [&](const IterationSummary& it) {
                                           run->callbacks.push_back(it);
                                         });
}

// What must hold in any run, whatever the script: one FinishStep per step
// with the history's decision; each step evaluated at the λ of the system it
// solved; the candidate is cameras ⊞ δc; cameras move to the candidate on an
// accepted step and stay exactly as they were on a rejected one; the cost in
// the history never rises; counts agree.
void ExpectConsistent(const ScriptedWorkers& w, const LmRun& run) {
  const LmSummary& s = run.summary;
  const size_t n = w.steps_taken();
  EXPECT_FALSE(w.pending()) << "the last step was neither kept nor dropped";
  EXPECT_EQ(s.iterations, static_cast<int>(n));
  ASSERT_EQ(s.history.size(), n);
  ASSERT_EQ(w.finished().size(), n);
  ASSERT_EQ(run.callbacks.size(), n);
  int accepted = 0;
  std::vector<double> current = InitialCameras();
  double cost = s.initial_cost;
  for (size_t i = 0; i < n; ++i) {
    const IterationSummary& it = s.history[i];
    EXPECT_EQ(it.iteration, static_cast<int>(i + 1));
    EXPECT_EQ(run.callbacks[i].iteration, it.iteration);
    EXPECT_EQ(run.callbacks[i].lambda, it.lambda);
    EXPECT_EQ(run.callbacks[i].step_accepted, it.step_accepted);
    EXPECT_EQ(it.step_accepted, w.finished()[i]) << "step " << i + 1;
    EXPECT_EQ(it.lambda, w.eval_lambdas()[i]) << "step " << i + 1;
    EXPECT_EQ(w.lambda_of_last_form()[i], w.eval_lambdas()[i])
        << "step " << i + 1 << " evaluated at another λ than its system was formed with";
    EXPECT_EQ(w.cameras_at_eval()[i], current) << "step " << i + 1;
    EXPECT_NE(w.deltas()[i], std::vector<double>(w.deltas()[i].size(), 0.0))
        << "step " << i + 1 << ": zero camera step";
    EXPECT_EQ(it.cost, cost) << "step " << i + 1;
    EXPECT_LE(it.cost, s.initial_cost);
    if (w.finished()[i]) {
      ++accepted;
      current = w.candidates()[i];
      EXPECT_LT(it.candidate_cost, cost) << "step " << i + 1 << " accepted a higher cost";
      cost = it.candidate_cost;
    }
  }
  EXPECT_EQ(s.accepted_iterations, accepted);
  EXPECT_EQ(run.cameras, current);
  EXPECT_EQ(s.final_cost, cost);
  EXPECT_EQ(s.final_cost, w.cost());
}

std::vector<bool> Accepted(const LmSummary& s) {
  std::vector<bool> a;
  for (const IterationSummary& it : s.history) a.push_back(it.step_accepted);
  return a;
}

std::vector<double> Lambdas(const LmSummary& s) {
  std::vector<double> l;
  for (const IterationSummary& it : s.history) l.push_back(it.lambda);
  return l;
}

// λ·max(1/3, 1 − (2ρ − 1)³) for the ρ used below, written out.
TEST(LmControl, LambdaAndNuFollowNielsensUpdate) {
  LmRun run;
  ScriptedWorkers w(100.0,
                    {Rising(),    // reject: λ 1 → 2, ν 2 → 4
                     Rising(),    // reject: λ 2 → 8, ν 4 → 8
                     Rho(1.0),    // accept, ρ = 1: factor 1/3, ν ← 2
                     Rising(),    // reject: λ ·2 (not ·8: ν was reset), ν → 4
                     Rho(0.75),   // accept, (2ρ−1)³ = 1/8: factor 7/8
                     Rho(0.25),   // accept, (2ρ−1)³ = −1/8: factor 9/8
                     Rising(),    // reject: λ ·2
                     Rising(),    // reject: λ ·4
                     Rho(0.5),    // accept, ρ = ½: factor 1
                     Rho(0.9),    // accept, (0.8)³ = 0.512: factor 0.488
                     Rho(2.0)},   // accept, ρ > 1: factor 1/3 (not 1 − 27)
                    &run.cameras);
  LmOptions options = Options();
  options.max_iterations = 11;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);

  const double l3 = 8.0 / 3.0, l5 = 2 * l3 * 7.0 / 8.0, l6 = l5 * 9.0 / 8.0,
               l9 = l6 * 8.0, l10 = l9, l11 = l10 * 0.488;
  const std::vector<double> want = {1.0, 2.0, 8.0, l3, 2 * l3, l5, l6, 2 * l6, l9, l10, l11};
  const std::vector<double> got = Lambdas(run.summary);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_NEAR(got[i], want[i], 1e-12 * want[i]) << "step " << i + 1;
  }
  // The step that reaches the iteration limit ends the solve itself: no
  // system is formed after it (the last one was formed for it), and it
  // records the next λ (a checkpoint written from it resumes with that).
  ASSERT_FALSE(w.form_lambdas().empty());
  EXPECT_NEAR(w.form_lambdas().back(), l11, 1e-12 * l11);
  EXPECT_TRUE(run.summary.history.back().ends_solve);
  EXPECT_EQ(run.summary.history.back().termination, TerminationReason::kMaxIterations);
  EXPECT_NEAR(run.summary.history.back().next_lambda, l11 / 3.0, 1e-12 * l11);

  EXPECT_EQ(Accepted(run.summary), (std::vector<bool>{false, false, true, false, true, true,
                                                      false, false, true, true, true}));
  ASSERT_EQ(w.finished(), Accepted(run.summary));
  const std::vector<double> rho = {-0.5, -0.5, 1.0, -0.5, 0.75, 0.25, -0.5, -0.5, 0.5, 0.9, 2.0};
  for (size_t i = 0; i < rho.size(); ++i) {
    EXPECT_NEAR(run.summary.history[i].gain_ratio, rho[i], 1e-12) << "step " << i + 1;
  }
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
  EXPECT_EQ(run.summary.iterations, 11);
  EXPECT_EQ(run.summary.accepted_iterations, 6);
  EXPECT_EQ(run.summary.initial_cost, 100.0);
  // 100 − 10 − 7.5 − 2.5 − 5 − 9 − 20
  EXPECT_NEAR(run.summary.final_cost, 46.0, 1e-12);
}

// A host's request to stop (common/interrupt.h: Python's Ctrl-C) is polled
// before each iteration: what its check throws leaves the loop there, with
// the steps before it taken and no later one started.
TEST(LmControl, AnInterruptCheckStopsTheLoopBetweenIterations) {
  LmRun run;
  ScriptedWorkers w(100.0, {Rho(1.0), Rho(1.0), Rho(1.0), Rho(1.0)}, &run.cameras);
  int polls = 0;
  const InterruptCheck check([&] {
    if (++polls == 3) throw std::runtime_error("interrupted");
  });
  LmOptions options = Options();
  options.max_iterations = 4;
  EXPECT_THROW(Solve(options, &w, &run), std::runtime_error);
  EXPECT_EQ(polls, 3);
  EXPECT_EQ(w.finished(), (std::vector<bool>{true, true}));
  EXPECT_EQ(run.callbacks.size(), 2u);
}

// A mixed-precision PCG's damping floor (solver/pcg.h): a good step that it
// holds up turns auto's product to double, and λ goes below the floor from
// the next step on; an explicit mixed product keeps the floor.
TEST(LmControl, TheDampingFloorIsDroppedWhenItHoldsAGoodStep) {
  for (PcgPrecision precision : {PcgPrecision::kAuto, PcgPrecision::kMixed}) {
    LmRun run;
    ScriptedWorkers w(100.0, {Rho(1.0), Rho(1.0), Rho(1.0), Rising(), Rho(1.0)}, &run.cameras);
    LmOptions options = Options();
    options.initial_lambda = 1e-7;
    options.max_iterations = 5;
    options.linear_solver.type = LinearSolverType::kPcg;
    options.linear_solver.pcg.precision = precision;
    Solve(options, &w, &run);
    ExpectConsistent(w, run);
    const double floor = kMixedPrecisionMinLambda;
    const std::vector<double> got = Lambdas(run.summary);
    ASSERT_EQ(got.size(), 5u);
    EXPECT_EQ(got[0], 1e-7);
    EXPECT_EQ(got[1], floor);  // 1e-7 / 3 held up, in either case
    if (precision == PcgPrecision::kAuto) {
      EXPECT_EQ(run.summary.pcg_double_from_iteration, 2);
      EXPECT_NEAR(got[2], floor / 3, 1e-20);
      EXPECT_NEAR(got[3], floor / 9, 1e-20);
      EXPECT_NEAR(got[4], 2 * floor / 9, 1e-20);  // rejected: ·2, no floor any more
    } else {
      EXPECT_EQ(run.summary.pcg_double_from_iteration, 0);
      EXPECT_EQ(got[2], floor);
      EXPECT_EQ(got[3], floor);
      EXPECT_EQ(got[4], 2 * floor);
    }
  }
}

// A resumed solve (io/checkpoint.h) whose λ is below the floor had dropped
// it: the product is double from its first step, and λ stays where it was.
TEST(LmControl, AResumedLambdaBelowTheFloorStartsWithoutIt) {
  LmRun run;
  ScriptedWorkers w(100.0, {Rho(1.0), Rho(1.0)}, &run.cameras);
  LmOptions options = Options();
  options.initial_lambda = 1e-8;
  options.max_iterations = 2;
  options.linear_solver.type = LinearSolverType::kPcg;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.pcg_double_from_iteration, 1);
  EXPECT_EQ(Lambdas(run.summary), (std::vector<double>{1e-8, 1e-8 / 3}));
  // At the floor exactly: where the floor held λ and was dropped.
  LmRun at;
  ScriptedWorkers w_at(100.0, {Rho(1.0)}, &at.cameras);
  options.initial_lambda = kMixedPrecisionMinLambda;
  options.max_iterations = 1;
  Solve(options, &w_at, &at);
  EXPECT_EQ(at.summary.pcg_double_from_iteration, 1);
}

// A drop after the last step names no iteration: no solve ran without it.
TEST(LmControl, AFloorDroppedAfterTheLastStepIsNotReported) {
  LmRun run;
  ScriptedWorkers w(100.0, {Rho(1.0)}, &run.cameras);
  LmOptions options = Options();
  options.initial_lambda = 1e-7;
  options.max_iterations = 1;
  options.linear_solver.type = LinearSolverType::kPcg;
  Solve(options, &w, &run);
  EXPECT_EQ(run.summary.iterations, 1);
  EXPECT_EQ(run.summary.pcg_double_from_iteration, 0);
}

TEST(LmControl, RejectedStepsDropTheCandidateAndKeepTheCameras) {
  LmRun run;
  ScriptedWorkers w(50.0, {Rising(), Rising(), Rising(), Rho(0.5)}, &run.cameras);
  LmOptions options = Options();
  options.max_iterations = 4;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  ASSERT_EQ(w.finished(), (std::vector<bool>{false, false, false, true}));
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(w.cameras_at_eval()[i], InitialCameras()) << "step " << i + 1;
  }
  EXPECT_EQ(run.cameras, w.candidates()[3]);
  EXPECT_NE(run.cameras, InitialCameras());
  ASSERT_EQ(run.summary.history.size(), 4u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(run.summary.history[i].cost, 50.0);
    EXPECT_EQ(run.summary.history[i].candidate_cost, 55.0);
  }
  EXPECT_EQ(run.summary.final_cost, 45.0);
}

// The camera step solves (S + λ D) δc = b with the λ of the step: the loop
// damps the camera blocks with the same λ as the points (FormRcs,
// EvaluateStep). S is diagonal here, so every linear solver finds
// δ_i = b_i / (S_ii + λ clamp(D_ii)).
TEST(LmControl, CameraStepIsDampedWithTheStepsLambda) {
  LmRun run;
  ScriptedWorkers w(100.0, {Rising(), Rising(), Rho(0.75)}, &run.cameras);
  LmOptions options = Options();
  options.max_iterations = 3;
  options.damping.min_diagonal = 3.0;  // clamps D_00..D_03 up to 3
  options.damping.max_diagonal = 8.0;  // and D_15..D_17 down to 8
  options.linear_solver.pcg.relative_tolerance = 1e-14;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  ASSERT_EQ(w.deltas().size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const double lambda = w.eval_lambdas()[k];
    const std::vector<double>& delta = w.deltas()[k];
    ASSERT_EQ(delta.size(), 18u);
    for (int64_t i = 0; i < 18; ++i) {
      const int32_t r = static_cast<int32_t>(i / kBalCameraSize);
      const int d = static_cast<int>(i % kBalCameraSize);
      const double want = ScriptedWorkers::B(i) / (ScriptedWorkers::Sii(r, d) +
                               lambda * options.damping.Clamp(ScriptedWorkers::Dii(i)));
      EXPECT_NEAR(delta[i], want, 1e-9 * std::abs(want)) << "step " << k + 1 << " unknown " << i;
    }
  }
}

TEST(LmControl, EveryKindOfBadStepIsRejected) {
  LmRun run;
  ScriptedWorkers w(100.0,
                    {Rising(),                       // the cost rises
                     Step{10.0, 0.0},                // ρ = 0: no decrease
                     Step{8.0, 2.0},                 // ρ = ¼ exactly: not above the minimum
                     Step{0.0, 5.0},                 // the model predicts no decrease
                     Step{-1.0, 5.0},                // the model predicts a rise
                     CandidateCost(kNaN),            // the cost cannot be evaluated
                     CandidateCost(kInf),
                     CandidateCost(-kInf),           // not finite, even if "lower"
                     Step{8.0, 2.5}},                // ρ = 0.3125: accepted
                    &run.cameras);
  LmOptions options = Options();
  options.min_relative_decrease = 0.25;
  options.max_iterations = 9;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  ASSERT_EQ(w.finished(), (std::vector<bool>{false, false, false, false, false, false, false,
                                             false, true}));
  // Eight rejections in a row: λ = 2^(1+2+...+8) λ0.
  EXPECT_EQ(run.summary.history.back().lambda, std::ldexp(1.0, 36));
  ASSERT_EQ(run.summary.history.size(), 9u);
  EXPECT_EQ(run.summary.history[3].gain_ratio, 0.0);
  EXPECT_EQ(run.summary.history[4].gain_ratio, 0.0);
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
}

TEST(LmControl, MaxIterationsCountsRejectedSteps) {
  LmRun run;
  ScriptedWorkers w(100.0, {Rho(0.5), Rising(), Rising()}, &run.cameras);
  LmOptions options = Options();
  options.max_iterations = 3;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
  EXPECT_STREQ(TerminationReasonName(run.summary.termination), "max_iterations");
  EXPECT_EQ(run.summary.iterations, 3);
  EXPECT_EQ(run.summary.accepted_iterations, 1);
}

TEST(LmControl, ZeroIterationsTakesNoStep) {
  LmRun run;
  ScriptedWorkers w(100.0, {}, &run.cameras);
  LmOptions options = Options();
  options.max_iterations = 0;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
  EXPECT_EQ(run.summary.iterations, 0);
  EXPECT_EQ(run.summary.final_cost, 100.0);
}

TEST(LmControl, LambdaTooLargeAfterRepeatedRejections) {
  LmRun run;
  // λ: 1 → 2 → 8 → 64 → 1024 > 100 after the fourth rejection.
  ScriptedWorkers w(100.0, {Rising(), Rising(), Rising(), Rising()}, &run.cameras);
  LmOptions options = Options();
  options.max_lambda = 100.0;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kLambdaTooLarge);
  EXPECT_STREQ(TerminationReasonName(run.summary.termination), "lambda_too_large");
  EXPECT_EQ(Lambdas(run.summary), (std::vector<double>{1.0, 2.0, 8.0, 64.0}));
  ASSERT_EQ(w.finished(), (std::vector<bool>{false, false, false, false}));
  EXPECT_EQ(run.cameras, InitialCameras());
  EXPECT_EQ(run.summary.final_cost, 100.0);
}

TEST(LmControl, LambdaAtTheLimitGoesOn) {
  LmRun run;
  // λ reaches exactly max_lambda = 64 after three rejections: not past it, so
  // the fourth step is tried (and accepted: λ stays 64, ν ← 2); the next
  // rejection takes λ past the limit.
  ScriptedWorkers w(100.0, {Rising(), Rising(), Rising(), Rho(0.5), Rising()}, &run.cameras);
  LmOptions options = Options();
  options.max_lambda = 64.0;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(Lambdas(run.summary), (std::vector<double>{1.0, 2.0, 8.0, 64.0, 64.0}));
  ASSERT_EQ(w.finished(), (std::vector<bool>{false, false, false, true, false}));
  EXPECT_EQ(run.summary.termination, TerminationReason::kLambdaTooLarge);
  EXPECT_EQ(run.summary.final_cost, 95.0);
}

TEST(LmControl, FunctionToleranceOnAnAcceptedStep) {
  LmRun run;
  // Relative decreases 1e-2, then 5e-4 ≤ 1e-3 (ρ = 0.5): stop after the
  // second step, which is kept.
  ScriptedWorkers w(100.0, {Step{2.0, 1.0}, Rising(), Step{0.099, 0.0495}}, &run.cameras);
  LmOptions options = Options();
  options.function_tolerance = 1e-3;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kFunctionTolerance);
  EXPECT_STREQ(TerminationReasonName(run.summary.termination), "function_tolerance");
  ASSERT_EQ(w.finished(), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(run.cameras, w.candidates()[2]);
  EXPECT_NEAR(run.summary.final_cost, 99.0 - 0.0495, 1e-12);
}

TEST(LmControl, APoorlyModelledStepWhoseModelPromisedLittleMeetsTheFunctionTolerance) {
  LmRun run;
  // ρ = 0.1 on a decrease of 5e-5 of the cost, whose model promised 5e-4:
  // both under the tolerance (near the optimum ρ is mostly rounding).
  ScriptedWorkers w(100.0, {Step{0.05, 0.005}, Rho(0.5)}, &run.cameras);
  LmOptions options = Options();
  options.function_tolerance = 1e-3;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kFunctionTolerance);
  ASSERT_EQ(w.finished(), (std::vector<bool>{true}));
}

TEST(LmControl, APoorlyModelledStepDoesNotMeetTheFunctionTolerance) {
  LmRun run;
  // ρ = 0.005: accepted (ρ > 1e-3), lowering the cost by 5e-4 of it (below
  // the tolerance), but a step of a poor model (ρ < 1/4): the loop goes on,
  // and stops after the next step, as small and well modelled (ρ = 0.5).
  ScriptedWorkers w(100.0, {Step{10.0, 0.05}, Step{0.1, 0.05}, Rho(0.5)}, &run.cameras);
  LmOptions options = Options();
  options.function_tolerance = 1e-3;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kFunctionTolerance);
  ASSERT_EQ(w.finished(), (std::vector<bool>{true, true}));
  EXPECT_NEAR(run.summary.final_cost, 100.0 - 0.1, 1e-12);
}

TEST(LmControl, RejectedStepsDoNotMeetTheFunctionTolerance) {
  LmRun run;
  // A rejected step decreases the cost by 0 (ρ = 0), far below the
  // tolerance: the loop goes on.
  ScriptedWorkers w(100.0, {Step{10.0, 0.0}, Step{10.0, -1e-9}, Rho(0.5)}, &run.cameras);
  LmOptions options = Options();
  options.function_tolerance = 1e-3;
  options.max_iterations = 3;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
  ASSERT_EQ(w.finished(), (std::vector<bool>{false, false, true}));
}

TEST(LmControl, GradientToleranceBeforeAnyStep) {
  LmRun run;
  ScriptedWorkers w(100.0, {}, &run.cameras);
  w.set_linearizations({Linearization{1e-13, 1e-13}});
  Solve(Options(), &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kGradientTolerance);
  EXPECT_STREQ(TerminationReasonName(run.summary.termination), "gradient_tolerance");
  EXPECT_EQ(run.summary.iterations, 0);
  EXPECT_EQ(run.cameras, InitialCameras());
}

TEST(LmControl, GradientToleranceAfterAcceptedSteps) {
  LmRun run;
  // The gradient is the max-norm over cameras and points: small on one side
  // only is not small.
  ScriptedWorkers w(100.0, {Rho(0.5), Rising(), Rho(0.5), Rho(0.5)}, &run.cameras);
  w.set_linearizations({Linearization{1.0, 1.0}, Linearization{1e-13, 1.0},
                        Linearization{1e-13, 1.0}, Linearization{1.0, 1e-13},
                        Linearization{1e-13, 1e-13}});
  Solve(Options(), &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kGradientTolerance);
  ASSERT_EQ(run.summary.iterations, 4);
  ASSERT_EQ(w.finished(), (std::vector<bool>{true, false, true, true}));
  EXPECT_EQ(run.summary.history[1].gradient_max_norm, 1.0);
  EXPECT_EQ(run.summary.history[3].gradient_max_norm, 1.0);
  EXPECT_EQ(run.cameras, w.candidates()[3]);
}

// A step with ‖δ‖ ≤ tol (‖x‖ + tol) ends the solve, whether ρ is good or
// bad, and is not applied.
TEST(LmControl, ParameterToleranceEndsOnATinyStepAndDropsIt) {
  for (const bool good : {true, false}) {
    SCOPED_TRACE(good ? "good tiny step" : "bad tiny step");
    LmRun run;
    // Steps 1 and 2 are ordinary (b ~ 1, ‖δX‖ = 1); step 3 has b ~ 1e-20
    // and δX = 0, so ‖δ‖ ~ 1e-20 against 1e-10 (‖x‖ + 1e-10), ‖x‖ > 1.
    Step tiny = good ? Rho(0.5) : Rising();
    tiny.point_step_squared_norm = 0.0;
    tiny.points_m2 = 4.0;
    ScriptedWorkers w(100.0, {Rho(0.5), Rising(), tiny}, &run.cameras);
    w.set_linearizations({Linearization{}, Linearization{}, Linearization{1.0, 1.0, 1e-20}});
    Solve(Options(), &w, &run);
    ExpectConsistent(w, run);
    EXPECT_EQ(run.summary.termination, TerminationReason::kParameterTolerance);
    EXPECT_STREQ(TerminationReasonName(run.summary.termination), "parameter_tolerance");
    EXPECT_EQ(run.summary.iterations, 3);
    ASSERT_EQ(w.finished(), (std::vector<bool>{true, false, false}));
    EXPECT_EQ(run.summary.accepted_iterations, 1);
    EXPECT_EQ(run.cameras, w.candidates()[0]);
    EXPECT_EQ(run.summary.final_cost, 95.0);
  }
}

// The point step counts in ‖δ‖: a zero-sized camera step with a real point
// step is not "converged".
TEST(LmControl, ParameterToleranceCountsThePointStep) {
  LmRun run;
  Step s = Rho(0.5);  // ‖δX‖ = 1
  ScriptedWorkers w(100.0, {s, s}, &run.cameras);
  w.set_linearizations({Linearization{1.0, 1.0, 1e-20}});
  LmOptions options = Options();
  options.max_iterations = 2;
  Solve(options, &w, &run);
  ExpectConsistent(w, run);
  EXPECT_EQ(run.summary.termination, TerminationReason::kMaxIterations);
  ASSERT_EQ(w.finished(), (std::vector<bool>{true, true}));
}

// A good step that ends the solve on the parameter tolerance is dropped
// (FinishStep(false); cameras, cost and accepted_iterations unchanged), and
// its history entry says so: `dba solve` prints "accepted no" for it.
TEST(LmControl, HistoryOfADroppedTinyStepSaysNotAccepted) {
  LmRun run;
  Step tiny = Rho(0.5);
  tiny.point_step_squared_norm = 0.0;
  ScriptedWorkers w(100.0, {tiny}, &run.cameras);
  w.set_linearizations({Linearization{1.0, 1.0, 1e-20}});
  Solve(Options(), &w, &run);
  ASSERT_EQ(run.summary.termination, TerminationReason::kParameterTolerance);
  ASSERT_EQ(w.finished(), std::vector<bool>{false});
  ASSERT_EQ(run.summary.accepted_iterations, 0);
  ASSERT_EQ(run.summary.history.size(), 1u);
  EXPECT_FALSE(run.summary.history[0].step_accepted);
}

}  // namespace
}  // namespace dba

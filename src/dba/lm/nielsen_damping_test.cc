// NielsenDamping: the λ and ν sequence of accepted and rejected steps.
#include "dba/lm/nielsen_damping.h"

#include <gtest/gtest.h>

namespace dba {
namespace {

TEST(NielsenDamping, AcceptedStepsScaleLambdaByTheGainRatio) {
  NielsenDamping d(1e-4);
  d.StepAccepted(1.0);  // 1 - 1³ = 0: the floor 1/3
  EXPECT_DOUBLE_EQ(d.lambda(), 1e-4 / 3.0);
  d.StepAccepted(0.5);  // 1 - 0 = 1: unchanged
  EXPECT_DOUBLE_EQ(d.lambda(), 1e-4 / 3.0);
  d.StepAccepted(0.25);  // 1 - (-0.5)³ = 1.125
  EXPECT_DOUBLE_EQ(d.lambda(), 1e-4 / 3.0 * 1.125);
  d.StepAccepted(0.0);  // 1 - (-1)³ = 2
  EXPECT_DOUBLE_EQ(d.lambda(), 1e-4 / 3.0 * 1.125 * 2.0);
  EXPECT_EQ(d.nu(), 2.0);
}

TEST(NielsenDamping, RejectionsDoubleNuAndAnAcceptanceResetsIt) {
  NielsenDamping d(1.0);
  d.StepRejected();
  d.StepRejected();
  d.StepRejected();
  EXPECT_DOUBLE_EQ(d.lambda(), 2.0 * 4.0 * 8.0);
  EXPECT_EQ(d.nu(), 16.0);
  d.StepAccepted(0.5);
  EXPECT_DOUBLE_EQ(d.lambda(), 64.0);
  EXPECT_EQ(d.nu(), 2.0);
  d.StepRejected();
  EXPECT_DOUBLE_EQ(d.lambda(), 128.0);
}

TEST(NielsenDamping, AcceptedStepsStopAtTheFloor) {
  NielsenDamping d(1e-7);
  d.SetFloor(4e-8);
  EXPECT_DOUBLE_EQ(d.lambda(), 1e-7);  // the floor acts from the next update
  d.StepAccepted(1.0);
  EXPECT_DOUBLE_EQ(d.lambda(), 4e-8);  // not 1e-7 / 3
  d.StepAccepted(1.0);
  EXPECT_DOUBLE_EQ(d.lambda(), 4e-8);
  d.StepRejected();
  EXPECT_DOUBLE_EQ(d.lambda(), 8e-8);
}

// The floor holding λ up is what turns a mixed product to double (the LM
// loop, RcsSolver::DropDampingFloor): only a good step it clamped counts.
TEST(NielsenDamping, SaysWhenTheFloorHeldLambdaUp) {
  NielsenDamping d(1e-7);
  d.SetFloor(4e-8);
  d.StepAccepted(1.0);  // 1e-7 / 3 wanted: below the floor
  EXPECT_TRUE(d.held_by_floor());
  d.StepRejected();     // 8e-8
  d.StepAccepted(0.5);  // unchanged: 8e-8, above the floor
  EXPECT_FALSE(d.held_by_floor());
  d.StepAccepted(0.9);  // 8e-8 * (1 - 0.8³) = 3.9e-8 < 4e-8
  EXPECT_TRUE(d.held_by_floor());
  d.SetFloor(0.0);
  d.StepAccepted(1.0);
  EXPECT_FALSE(d.held_by_floor());
  EXPECT_DOUBLE_EQ(d.lambda(), 4e-8 / 3.0);
}

}  // namespace
}  // namespace dba

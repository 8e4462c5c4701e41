// A solve stopped from outside; see interrupt.h.
#include "dba/common/interrupt.h"

#include <utility>

namespace dba {
namespace {

thread_local const std::function<void()>* installed = nullptr;

}  // namespace

InterruptCheck::InterruptCheck(std::function<void()> check)
    : check_(std::move(check)), previous_(installed) {
  installed = &check_;
}

InterruptCheck::~InterruptCheck() { installed = previous_; }

void PollInterrupt() {
  if (installed != nullptr) (*installed)();
}

}  // namespace dba

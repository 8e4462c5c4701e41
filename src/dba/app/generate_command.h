// `dba generate OUTPUT [options]`: a synthetic UAV survey with ground truth.
#pragma once

#include <string>
#include <vector>

namespace dba {

int GenerateMain(const std::vector<std::string>& args);

}  // namespace dba

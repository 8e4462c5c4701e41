// `dba convert IN OUT` and `dba info FILE`.
#pragma once

#include <string>
#include <vector>

namespace dba {

int ConvertMain(const std::vector<std::string>& args);
int InfoMain(const std::vector<std::string>& args);

}  // namespace dba

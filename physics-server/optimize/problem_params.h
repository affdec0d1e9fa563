// A problem's parameters against what its programs declare (hal_param_table,
// read from the programs: cosim/program_params.h): the base scene's own, and
// every parameter gene's name and whole range. Apart from the problem
// loader, which starts no process.
#pragma once

#include <string>

#include "optimize/problem.h"

namespace chainsim {

// throws ProblemError at the gene's (or the base scene's) file:line:column.
// The genes are checked against the programs of the first and the last
// individual's scene (every gene at its lowest, then its highest value):
// with a chain genome these two may not hold every module type.
void check_problem_params(const Problem& problem, const std::string& firmware_dir);

}  // namespace chainsim

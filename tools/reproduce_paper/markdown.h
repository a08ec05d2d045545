#pragma once
// docs/paper-reproduction.md: per figure the curve the model gives, the direction the paper
// claims, whether they agree and, where they do not, the mechanism.

#include <string>

#include "tools/reproduce_paper/output.h"
#include "tools/reproduce_paper/results.h"

namespace rollgap::tools::paper {

std::string write_markdown(const Results& R, const Output& out);

}  // namespace rollgap::tools::paper

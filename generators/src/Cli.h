// The wirenet-gen command line: subcommand dispatch, options, validation, summaries.
#pragma once
#include <string>
#include <vector>

namespace wirenet {

// Runs one invocation; returns the process exit code (0 ok, 2 bad input).
int runCli(const std::vector<std::string>& args);

}  // namespace wirenet

/// @file MachineInfo.h
/// Describes the machine a benchmark ran on, for the report header.
#pragma once

#include <string>

namespace tg::bench {

/// "<CPU model name from /proc/cpuinfo>, <N> cores" where N counts hardware threads (what
/// --threads defaults to); "unknown CPU, ..." when /proc/cpuinfo is unavailable.
std::string machineDescription();

/// Number of hardware threads (at least 1).
int hardwareThreads();

}  // namespace tg::bench

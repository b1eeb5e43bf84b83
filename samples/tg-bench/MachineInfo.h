/// @file MachineInfo.h
/// Describes the machine a benchmark ran on, for the report header.
#pragma once

#include <string>

namespace tg::bench {

/// "<CPU model name from /proc/cpuinfo>, <N> cores, SIMD <kernel>" where N counts hardware
/// threads (what --threads defaults to) and <kernel> is the packet kernel in use (tg::SimdIsa,
/// TG_SIMD overrides it); "unknown CPU, ..." when /proc/cpuinfo is unavailable.
std::string machineDescription();

/// Number of hardware threads (at least 1).
int hardwareThreads();

}  // namespace tg::bench
